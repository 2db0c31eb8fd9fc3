// Debian's Chromium, headless, driven by playwright-core (no browser of its own), as the view's
// browser tests and benchmarks start it: a fresh profile, no network of its own, 1400 x 800.
// And the robot table's GCS columns, as the tests read them.
const fs = require('node:fs');
const os = require('node:os');
const path = require('node:path');
const { chromium } = require('playwright-core');

const kChromium = '/usr/bin/chromium';

// A page in a new browser; close() ends the browser and removes its profile.
async function openBrowser() {
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), 'sitlnet-view-chromium-'));
  const context = await chromium.launchPersistentContext(profile, {
    executablePath: kChromium,
    headless: true,
    viewport: { width: 1400, height: 800 },
    args: ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run',
      '--disable-background-networking', '--disable-component-update', '--disable-sync'],
  });
  const page = context.pages()[0] ?? (await context.newPage());
  const close = async () => {
    await context.close();
    fs.rmSync(profile, { recursive: true, force: true });
  };
  return { context, page, close };
}

// Prints "console_error TEXT" for every console error, page error, failed request and HTTP error.
function printErrors(page) {
  page.on('console', (m) => { if (m.type() === 'error') console.log(`console_error ${m.text()}`); });
  page.on('pageerror', (e) => console.log(`console_error ${e.message}`));
  page.on('requestfailed', (r) => console.log(`console_error failed ${r.url()}`));
  page.on('response', (r) => {
    if (r.status() >= 400) console.log(`console_error ${r.status()} ${r.url()}`);
  });
}

// The robot table's rows as [index, system id, GCS mode, armed, loss], "-" where empty and
// spaces in a mode as "_" (one word a field).
async function gcsRows(page) {
  return page.$$eval('#robots tbody tr', (trs) => trs.map((tr) => [tr.dataset.robot,
    tr.dataset.systemId, tr.dataset.gcsMode, tr.dataset.armed, tr.dataset.loss]
    .map((v) => (v === undefined || v === '' ? '-' : v.replace(/ /g, '_')))));
}

// Saves a full-page screenshot of `page` as ARTIFACTS/NAME and prints "screenshot PATH".
async function screenshot(page, artifacts, name) {
  const file = path.join(artifacts, name);
  await page.screenshot({ path: file, fullPage: true });
  console.log(`screenshot ${file}`);
}

// Runs a driver's async `main`; an error it throws is printed as "console_error driver: ..."
// (the tests' failure line) and the exit status is 1.
function runDriver(main) {
  main().catch((error) => {
    console.log(`console_error driver: ${error.message.split('\n')[0]}`);
    process.exitCode = 1;
  });
}

module.exports = { gcsRows, openBrowser, printErrors, runDriver, screenshot };
