// SPDX-License-Identifier: GPL-3.0-or-later
// Cross-site control (issue 28 item 2) in headless Chromium: a page of another site (http://evil.example,
// resolved to loopback by the browser's host rules) that opens ws://127.0.0.1:PORT/live gets no session —
// the upgrade is refused (403), the socket never opens, the server is not driven — while the same page from
// a loopback origin connects and gets its hello.
// usage: node origin_test.js SERVE_PORT PAGE_PORT   (NODE_PATH holds playwright-core; PAGE_PORT serves attack.html)
'use strict';
const { chromium } = require('playwright-core');
(async () => {
  const [servePort, pagePort] = process.argv.slice(2);
  const browser = await chromium.launch({ executablePath: '/usr/bin/chromium', args: ['--no-sandbox', '--host-resolver-rules=MAP evil.example 127.0.0.1'] });
  const result = async (origin) => {
    const page = await browser.newPage();
    await page.goto(`${origin}/attack.html#${servePort}`);
    await page.waitForFunction(() => window.outcome !== undefined, null, { timeout: 15000 });
    const r = await page.evaluate(() => window.outcome);
    await page.close();
    return r;
  };
  const evil = await result(`http://evil.example:${pagePort}`);
  if (evil.opened || evil.hello) throw new Error('a page of another site opened a session: ' + JSON.stringify(evil));
  const local = await result(`http://127.0.0.1:${pagePort}`);
  if (!local.opened || !local.hello) throw new Error('a loopback page could not open a session: ' + JSON.stringify(local));
  await browser.close();
  console.log(`origin: http://evil.example:${pagePort} refused (close ${evil.code}), http://127.0.0.1:${pagePort} served`);
})().catch((e) => { console.error('origin_test: ' + e.message); process.exit(1); });
