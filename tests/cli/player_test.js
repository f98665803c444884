// SPDX-License-Identifier: GPL-3.0-or-later
// The browser test player (issue 14) in headless Chromium: participant 2 answers every stimulus by
// keyboard only; the CSV must list the stimuli in order-02.csv's order with the answers given.
// usage: node player_test.js OUTDIR   (NODE_PATH holds playwright-core)
'use strict';
const fs = require('fs');
const path = require('path');
const { chromium } = require('playwright-core');
(async () => {
  const dir = process.argv[2];
  const order = fs.readFileSync(path.join(dir, 'order-02.csv'), 'utf8').trim().split('\n').slice(1).map((l) => l.split(',')[1]);
  const browser = await chromium.launch({ executablePath: '/usr/bin/chromium', args: ['--autoplay-policy=no-user-gesture-required', '--no-sandbox'] });
  const page = await browser.newPage();
  const errors = [];
  page.on('pageerror', (e) => errors.push(e.message));
  page.on('request', (r) => { if (!r.url().startsWith('file://') && !r.url().startsWith('blob:')) errors.push('network request: ' + r.url()); });
  await page.goto('file://' + path.resolve(dir, 'index.html'));
  // A participant number out of range is refused.
  await page.keyboard.type('99');
  await page.keyboard.press('Enter');
  if (!(await page.textContent('#startError')).includes('from 1 to')) throw new Error('participant 99 accepted');
  await page.fill('#pid', '2');
  await page.keyboard.press('Enter');
  const expect = [];
  for (let k = 0; k < order.length; ++k) {
    for (const phase of ['valence', 'emotion']) {
      await page.waitForSelector('#answer:not([hidden])', { timeout: 20000 });
      if (await page.textContent('#videoError')) throw new Error('video cannot play: ' + order[k]);
      // Keyboard only: focus is on the first choice; ArrowDown k+1 times, then Enter confirms.
      for (let i = 0; i <= k; ++i) await page.keyboard.press('ArrowDown');
      const chosen = await page.evaluate(() => document.querySelector('input[name=choice]:checked').value);
      expect.push(chosen);
      await page.keyboard.press('Enter');
    }
  }
  await page.waitForSelector('#done:not([hidden])', { timeout: 20000 });
  const csv = (await page.textContent('#csv')).trim().split('\n');
  await browser.close();
  if (errors.length) throw new Error(errors.join('; '));
  if (csv[0] !== 'participant,position,id,valence,valence_ms,emotion,emotion_ms') throw new Error('header: ' + csv[0]);
  if (csv.length !== order.length + 1) throw new Error(csv.length - 1 + ' answers for ' + order.length + ' stimuli');
  for (let k = 0; k < order.length; ++k) {
    const f = csv[k + 1].split(',');
    if (f[0] !== '2' || f[1] !== String(k + 1) || f[2] !== order[k]) throw new Error('row ' + (k + 1) + ': ' + csv[k + 1]);
    if (f[3] !== expect[2 * k] || f[5] !== expect[2 * k + 1]) throw new Error('answers of row ' + (k + 1) + ': ' + csv[k + 1]);
    if (!(Number(f[4]) >= 0 && Number(f[6]) >= 0)) throw new Error('response times: ' + csv[k + 1]);
  }
  console.log('player: ' + order.length + ' stimuli answered by keyboard, CSV matches order-02.csv');
})().catch((e) => { console.error('player_test: ' + e.message); process.exit(1); });
