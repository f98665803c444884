// SPDX-License-Identifier: GPL-3.0-or-later
// The live demo page (issue 16) in headless Chromium: it connects, a sentence is sent, the video element
// plays (Media Source Extensions, H.264 + AAC), its currentTime advances, and the events arrive.
// usage: node demo_test.js URL [FRAGMENT [WAV]]   (NODE_PATH holds playwright-core; FRAGMENT e.g. token=… for a
// server that asks for a token, '' for none; WAV: a sound file to speak with the page's "speak a WAV")
'use strict';
const { chromium } = require('playwright-core');
(async () => {
  const url = process.argv[2], fragment = process.argv[3] || '';
  const browser = await chromium.launch({ executablePath: '/usr/bin/chromium', args: ['--autoplay-policy=no-user-gesture-required', '--no-sandbox'] });
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('request', (r) => { if (!r.url().startsWith(url) && !r.url().startsWith('ws') && !r.url().startsWith('blob:')) errors.push('request outside the server: ' + r.url()); });
  await page.goto(fragment ? url + '#' + fragment : url);
  await page.click('#connect');
  await page.waitForFunction(() => window.events.some((e) => e.type === 'hello'), null, { timeout: 20000 });
  const mime = await page.evaluate(() => window.events.find((e) => e.type === 'hello').mime);
  if (!(await page.evaluate((m) => MediaSource.isTypeSupported(m), mime))) throw new Error('Chromium cannot play ' + mime);
  await page.fill('#text', 'Good morning. The weather is lovely today.');
  await page.selectOption('#emotion', 'joy');
  await page.click('#say');
  await page.waitForFunction(() => window.events.some((e) => e.type === 'utterance_started' && e.id === 'u1'), null, { timeout: 20000 });
  // The video plays and its time advances while the face speaks.
  await page.waitForFunction(() => { const v = document.querySelector('#face'); return !v.paused && v.currentTime > 0.5 && v.readyState >= 3; }, null, { timeout: 20000 });
  const t0 = await page.evaluate(() => document.querySelector('#face').currentTime);
  await page.waitForTimeout(1500);
  const t1 = await page.evaluate(() => document.querySelector('#face').currentTime);
  if (!(t1 - t0 > 1.0)) throw new Error('currentTime went from ' + t0 + ' to ' + t1 + ' in 1.5 s');
  await page.waitForFunction(() => window.events.some((e) => e.type === 'utterance_ended' && e.id === 'u1'), null, { timeout: 20000 });
  const ev = await page.evaluate(() => window.events.map((e) => e.type));
  for (const need of ['hello', 'emotion', 'utterance_started', 'viseme', 'utterance_ended'])
    if (!ev.includes(need)) throw new Error('no ' + need + ' event (got ' + [...new Set(ev)].join(', ') + ')');
  // Issue 49: "speak a WAV" — a sound file alone (the server recognises its phones), then with the text.
  const wav = process.argv[4];
  if (wav) {
    await page.setInputFiles('#wav', wav);
    await page.click('#speakwav');
    await page.waitForFunction(() => window.events.some((e) => e.type === 'utterance_ended' && e.id === 'w2'), null, { timeout: 30000 });
    await page.fill('#text', 'Good morning, how can I help you today?');
    await page.check('#wavtext');
    await page.click('#speakwav');
    await page.waitForFunction(() => window.events.some((e) => e.type === 'utterance_ended' && e.id === 'w3'), null, { timeout: 30000 });
    // Streamed in PCM pieces with its text: one utterance, started once and ended once.
    await page.check('#wavstream');
    await page.click('#speakwav');
    await page.waitForFunction(() => window.events.some((e) => e.type === 'utterance_ended' && e.id === 'w4'), null, { timeout: 30000 });
    const starts = await page.evaluate(() => window.events.filter((e) => e.type === 'utterance_started' && e.id === 'w4').length);
    if (starts !== 1) throw new Error('the streamed WAV started ' + starts + ' times');
    if (await page.evaluate(() => window.events.some((e) => e.type === 'error'))) throw new Error('an error event after speaking the WAV');
  }
  const size = await page.evaluate(() => [document.querySelector('#face').videoWidth, document.querySelector('#face').videoHeight]);
  await browser.close();
  if (errors.length) throw new Error(errors.join('; '));
  console.log('demo: connected, played ' + mime + ' at ' + size.join('x') + ', currentTime ' + t0.toFixed(2) + ' -> ' + t1.toFixed(2) + ' s, ' + ev.length + ' events');
})().catch((e) => { console.error('demo_test: ' + e.message); process.exit(1); });
