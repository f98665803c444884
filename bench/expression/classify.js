// SPDX-License-Identifier: GPL-3.0-or-later
// Independent facial-expression judgement for bench/expression.sh: face-api's 7-class expression net
// (@vladmandic/face-api, SSD MobileNet v1 face detector, TensorFlow.js on its WebAssembly backend, all
// from npm; nothing of talkhead's). Reads a YUV4MPEG2 stream (C420, BT.601 limited range, as
// `talkhead render --format y4m -o -` writes it) on standard input, judges every N-th frame and prints
// one JSON line: frames judged, frames with a face, and the mean of the 7 class probabilities over the
// frames with a face.  usage: node classify.js [EVERY_NTH] < clip.y4m
'use strict';
const path = require('path');
const faceapi = require('@vladmandic/face-api/dist/face-api.node-wasm.js');
const tf = faceapi.tf;
const classes = ['neutral', 'happy', 'sad', 'angry', 'fearful', 'disgusted', 'surprised'];
const every = Math.max(1, parseInt(process.argv[2] || '3', 10));

async function readAll(stream) {
  const chunks = [];
  for await (const c of stream) chunks.push(c);
  return Buffer.concat(chunks);
}

function frames(buf) {
  const nl = buf.indexOf(10);
  const header = buf.subarray(0, nl).toString('latin1');
  if (!header.startsWith('YUV4MPEG2 ')) throw new Error('standard input: not a YUV4MPEG2 stream');
  const w = +/ W(\d+)/.exec(header)[1], h = +/ H(\d+)/.exec(header)[1];
  if (!/ C420/.test(header) && / C/.test(header)) throw new Error('standard input: only 4:2:0 streams');
  const cw = w >> 1, ch = h >> 1, size = w * h + 2 * cw * ch;
  const out = [];
  let pos = nl + 1;
  while (pos < buf.length) {
    const e = buf.indexOf(10, pos);
    if (e < 0 || !buf.subarray(pos, pos + 5).equals(Buffer.from('FRAME'))) throw new Error('standard input: bad FRAME header');
    pos = e + 1;
    if (pos + size > buf.length) throw new Error('standard input: truncated frame');
    out.push({ w, h, data: buf.subarray(pos, pos + size) });
    pos += size;
  }
  return out;
}

function toRgb({ w, h, data }) {
  const cw = w >> 1, rgb = new Int32Array(w * h * 3);
  const U = w * h, V = U + cw * (h >> 1);
  for (let y = 0; y < h; ++y)
    for (let x = 0; x < w; ++x) {
      const c = (y >> 1) * cw + (x >> 1);
      const Y = 1.164383 * (data[y * w + x] - 16), u = data[U + c] - 128, v = data[V + c] - 128;
      const i = (y * w + x) * 3;
      rgb[i] = Math.min(255, Math.max(0, Math.round(Y + 1.596027 * v)));
      rgb[i + 1] = Math.min(255, Math.max(0, Math.round(Y - 0.391762 * u - 0.812968 * v)));
      rgb[i + 2] = Math.min(255, Math.max(0, Math.round(Y + 2.017232 * u)));
    }
  return tf.tensor3d(rgb, [h, w, 3], 'int32');
}

(async () => {
  faceapi.tf.setWasmPaths(path.join(path.dirname(require.resolve('@tensorflow/tfjs-backend-wasm')), '/'));
  await tf.setBackend('wasm');
  await tf.ready();
  const models = path.join(path.dirname(require.resolve('@vladmandic/face-api/package.json')), 'model');
  await faceapi.nets.ssdMobilenetv1.loadFromDisk(models);
  await faceapi.nets.faceLandmark68Net.loadFromDisk(models);
  await faceapi.nets.faceExpressionNet.loadFromDisk(models);
  const all = frames(await readAll(process.stdin));
  const sum = Object.fromEntries(classes.map((c) => [c, 0]));
  let judged = 0, faces = 0;
  for (let i = 0; i < all.length; i += every) {
    const t = toRgb(all[i]);
    const r = await faceapi.detectSingleFace(t, new faceapi.SsdMobilenetv1Options({ minConfidence: 0.3 })).withFaceLandmarks().withFaceExpressions();
    t.dispose();
    ++judged;
    if (!r) continue;
    ++faces;
    for (const c of classes) sum[c] += r.expressions[c];
  }
  const mean = Object.fromEntries(classes.map((c) => [c, faces ? +(sum[c] / faces).toFixed(4) : 0]));
  console.log(JSON.stringify({ frames: all.length, judged, faces, mean }));
})().catch((e) => { console.error('classify.js: ' + e.message); process.exit(1); });
