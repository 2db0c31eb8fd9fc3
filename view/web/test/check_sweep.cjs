// Drives the sweep page of `sitlnet view SWEEP_DIR` in Debian's Chromium for
// tests/integration/view_browser_test.cc (ViewBrowserTest.ASweepsPage...), which holds the
// oracles (the sweep's own summary.csv and points.csv).
// Usage: node check_sweep.cjs URL ARTIFACT_DIR
// Prints one fact a line:
//   console_error TEXT                     every console error, page error and failed request
//   plot METRIC FIELD LINES                a plot drawn, and how many lines it has
//   mark METRIC FIELD X MEAN HALF LABEL    a mark of it: the numbers it was drawn from, and its
//                                          line's label (the other fields' values)
//   table ID ROWS COLUMNS                  a table's body rows and header cells
//   failed_rows N                          points rows marked failed
//   screenshot PATH
const fs = require('node:fs');
const { openBrowser, printErrors, runDriver, screenshot } = require('./browser.cjs');

async function main() {
  const [url, artifacts] = process.argv.slice(2);
  fs.mkdirSync(artifacts, { recursive: true });
  const { page, close } = await openBrowser();
  try {
    printErrors(page);
    await page.goto(url);
    await page.waitForSelector('body[data-ready="true"], body[data-error]', { timeout: 30000 });
    const error = await page.$eval('body', (b) => b.dataset.error ?? '');
    if (error !== '') console.log(`console_error page: ${error}`);
    const facts = await page.evaluate(() => ({
      plots: [...document.querySelectorAll('figure.sweep-plot')].map((f) => ({
        metric: f.dataset.metric,
        field: f.dataset.field,
        lines: f.querySelectorAll('g.line').length,
        marks: [...f.querySelectorAll('g.mark')].map((m) => [m.dataset.x, m.dataset.mean, m.dataset.half,
          m.closest('g.line').dataset.label]),
      })),
      tables: ['summary', 'points'].map((id) => [id,
        document.querySelectorAll(`#${id} tbody tr`).length,
        document.querySelectorAll(`#${id} thead th`).length]),
      failed: document.querySelectorAll('#points tbody tr[data-status="failed"]').length,
    }));
    for (const p of facts.plots) {
      console.log(`plot ${p.metric} ${p.field} ${p.lines}`);
      for (const m of p.marks) console.log(`mark ${p.metric} ${p.field} ${m.join(' ')}`);
    }
    for (const t of facts.tables) console.log(`table ${t.join(' ')}`);
    console.log(`failed_rows ${facts.failed}`);
    await screenshot(page, artifacts, 'sweep.png');
  } finally {
    await close();
  }
}

runDriver(main);
