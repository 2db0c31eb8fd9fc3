// One plot of the sweep page: a metric's mean against one swept field, a line per combination
// of the other fields, the 95 % interval as bars (as sitlnet sweep's PNGs draw it). Each mark
// carries data-x, data-mean and data-half (the numbers drawn), for tests.
import { scaleLinear, scalePoint } from 'd3-scale';

const kWidthPx = 440;
const kHeightPx = 260;
const kMargin = { left: 70, right: 16, top: 12, bottom: 40 };
const kColours = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#8c564b'];

// summary.csv's rows of `metric` as series against `field`: [{label, points: [{x, mean, half}]}],
// points in ascending x (numbers) or in the order met (other values). Null when the field takes
// fewer than two values (nothing to plot against) or no row of the metric has a finite mean; a
// row without one is left out, and an undefined half-width draws no bar.
export function plotSeries(summary, fields, field, metric) {
  // summary.csv writes %.10g: a mean of inf or nan reads as a number that cannot be drawn.
  const rows = summary.filter((row) => row.metric === metric && row.mean !== '' &&
    Number.isFinite(Number(row.mean)));
  const values = [...new Set(summary.map((row) => row[field]))];
  if (values.length < 2 || rows.length === 0) return null;
  const others = fields.filter((f) => f !== field);
  const byLabel = new Map();
  for (const row of rows) {
    const label = others.map((f) => `${f}=${row[f]}`).join(', ');
    if (!byLabel.has(label)) byLabel.set(label, []);
    byLabel.get(label).push({
      x: row[field],
      mean: Number(row.mean),
      half: Number.isFinite(Number(row.ci95_half_width)) && row.ci95_half_width !== ''
        ? Number(row.ci95_half_width) : 0,
    });
  }
  const numeric = values.every((v) => v !== '' && Number.isFinite(Number(v)));
  const order = (a, b) => (numeric ? Number(a.x) - Number(b.x) : values.indexOf(a.x) - values.indexOf(b.x));
  return {
    numeric,
    values,
    lines: [...byLabel].map(([label, points]) => ({ label, points: points.sort(order) })),
  };
}

// Draws `series` (plotSeries) into `figure` (a d3 selection).
export function drawMetricPlot(figure, metric, field, series) {
  figure.attr('class', 'sweep-plot').attr('data-metric', metric).attr('data-field', field);
  const svg = figure.append('svg').attr('width', kWidthPx).attr('height', kHeightPx);
  const all = series.lines.flatMap((line) => line.points);
  const low = Math.min(...all.map((p) => p.mean - p.half));
  const high = Math.max(...all.map((p) => p.mean + p.half));
  const pad = high > low ? 0.05 * (high - low) : Math.max(Math.abs(high), 1) * 0.05;
  const y = scaleLinear().domain([low - pad, high + pad])
    .range([kHeightPx - kMargin.bottom, kMargin.top]).nice();
  const x = series.numeric
    ? scaleLinear().domain([Math.min(...series.values.map(Number)), Math.max(...series.values.map(Number))])
      .range([kMargin.left + 10, kWidthPx - kMargin.right - 10])
    : scalePoint().domain(series.values).range([kMargin.left + 10, kWidthPx - kMargin.right - 10]);
  const xOf = (value) => (series.numeric ? x(Number(value)) : x(value));
  const axis = svg.append('g').attr('class', 'axis');
  axis.append('line').attr('x1', kMargin.left).attr('x2', kWidthPx - kMargin.right)
    .attr('y1', kHeightPx - kMargin.bottom).attr('y2', kHeightPx - kMargin.bottom);
  axis.append('line').attr('x1', kMargin.left).attr('x2', kMargin.left)
    .attr('y1', kMargin.top).attr('y2', kHeightPx - kMargin.bottom);
  for (const tick of y.ticks(5)) {
    axis.append('text').attr('x', kMargin.left - 6).attr('y', y(tick) + 4)
      .attr('text-anchor', 'end').text(String(tick));
  }
  for (const value of series.values) {
    axis.append('text').attr('x', xOf(value)).attr('y', kHeightPx - kMargin.bottom + 16)
      .attr('text-anchor', 'middle').text(value);
  }
  axis.append('text').attr('x', (kMargin.left + kWidthPx) / 2).attr('y', kHeightPx - 6)
    .attr('text-anchor', 'middle').text(field);
  series.lines.forEach((line, i) => {
    const colour = kColours[i % kColours.length];
    const g = svg.append('g').attr('class', 'line').attr('data-label', line.label);
    g.append('polyline').attr('fill', 'none').attr('stroke', colour)
      .attr('points', line.points.map((p) => `${xOf(p.x)},${y(p.mean)}`).join(' '));
    for (const p of line.points) {
      const mark = g.append('g').attr('class', 'mark').attr('data-x', p.x)
        .attr('data-mean', p.mean).attr('data-half', p.half);
      mark.append('line').attr('stroke', colour).attr('x1', xOf(p.x)).attr('x2', xOf(p.x))
        .attr('y1', y(p.mean - p.half)).attr('y2', y(p.mean + p.half));
      mark.append('circle').attr('fill', colour).attr('r', 3).attr('cx', xOf(p.x)).attr('cy', y(p.mean));
    }
  });
  const caption = figure.append('figcaption').text(`${metric} against ${field}`);
  if (series.lines.length > 1 || series.lines[0]?.label) {
    series.lines.forEach((line, i) => {
      caption.append('span').attr('class', 'swatch').style('background', kColours[i % kColours.length]);
      caption.append('span').text(line.label);
    });
  }
}
