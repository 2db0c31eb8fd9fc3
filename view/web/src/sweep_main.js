// The page of `sitlnet view SWEEP_DIR`: summary.csv's means and intervals plotted against each
// swept field, and both tables (docs/sweep-reference.md). document.body's data-ready is "true"
// once drawn, or data-error holds why not.
import { select } from 'd3-selection';
import { csvParseRows } from 'd3-dsv';
import { loadSweep } from './api.js';
import { drawMetricPlot, plotSeries } from './sweep_plot.js';

// summary.csv's columns before these are the swept fields (docs/sweep-reference.md).
const kSummaryColumns = ['metric', 'n', 'mean', 'sd', 'ci95_half_width'];

// A CSV table as row objects with a `columns` list. csvParseRows, not csvParse: csvParse builds
// its row objects with `new Function`, which the page's Content-Security-Policy forbids.
function parseCsv(text) {
  const [columns = [], ...rows] = csvParseRows(text);
  const objects = rows.map((row) => Object.fromEntries(columns.map((c, i) => [c, row[i] ?? ''])));
  objects.columns = columns;
  return objects;
}

function drawTable(selector, columns, rows) {
  const table = select(selector);
  table.select('thead').selectAll('tr').data([columns]).join('tr')
    .selectAll('th').data((c) => c).join('th').text((c) => c);
  table.select('tbody').selectAll('tr').data(rows).join('tr')
    .attr('data-status', (row) => row.status ?? null)
    .selectAll('td').data((row) => columns.map((c) => row[c])).join('td').text((v) => v);
}

async function main() {
  const sweep = await loadSweep();
  select('#title').text(`sitlnet sweep: ${sweep.folder}`);
  const summary = parseCsv(sweep.summary_csv);
  const points = parseCsv(sweep.points_csv);
  const fields = summary.columns.slice(0, summary.columns.length - kSummaryColumns.length);
  drawTable('#summary', summary.columns, summary);
  drawTable('#points', points.columns, points);
  const failed = points.filter((p) => p.status !== 'ok').length;
  select('#points-note').text(`${points.length} points, ${failed} not finished or failed.`);
  const metrics = [...new Set(summary.map((row) => row.metric))];
  const plots = select('#plots');
  for (const metric of metrics) {
    for (const field of fields) {
      const series = plotSeries(summary, fields, field, metric);
      if (series === null) continue;
      drawMetricPlot(plots.append('figure'), metric, field, series);
    }
  }
  document.body.dataset.ready = 'true';
}

main().catch((error) => {
  document.body.dataset.error = String(error.message ?? error);
  select('main').insert('p', ':first-child').attr('class', 'error').text(String(error));
});
