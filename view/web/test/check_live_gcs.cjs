// Reads the live page of `sitlnet run --view --gcs ...` in Debian's Chromium for
// tests/integration/view_browser_test.cc (ViewBrowserTest.TheLiveViewShows...): waits until the
// robot table shows VEHICLES armed vehicles, then prints the table's GCS columns and each map
// label's second line.
// Usage: node check_live_gcs.cjs URL ARTIFACT_DIR VEHICLES
// Prints: console_error TEXT; gcs INDEX SYSTEM_ID MODE ARMED LOSS ("-": none, "_" for a space);
//         status INDEX TEXT (a label's second line); screenshot PATH
const fs = require('node:fs');
const { gcsRows, openBrowser, printErrors, runDriver, screenshot } = require('./browser.cjs');

async function main() {
  const [url, artifacts, vehicles] = process.argv.slice(2);
  fs.mkdirSync(artifacts, { recursive: true });
  const { page, close } = await openBrowser();
  try {
    printErrors(page);
    await page.goto(url);
    await page.waitForFunction((n) =>
      document.querySelectorAll('#robots tbody tr[data-armed="true"]').length >= n,
    Number(vehicles), { timeout: 60000, polling: 250 });
    for (const row of await gcsRows(page)) console.log(`gcs ${row.join(' ')}`);
    const statuses = await page.$$eval('#map text.robot-label', (labels) =>
      labels.map((l) => [l.dataset.robot, l.dataset.status ?? '']));
    for (const [index, status] of statuses) console.log(`status ${index} ${status}`);
    await screenshot(page, artifacts, 'live-gcs.png');
  } finally {
    await close();
  }
}

runDriver(main);
