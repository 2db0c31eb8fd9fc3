// The timeline under the map: connectivity components (connectivity.csv, where they change),
// and per simulated second the iterations' STF and lag (metrics.csv), with a cursor at the
// time shown. The svg's data attributes say what is shown at the cursor, for tests.
import { select } from 'd3-selection';
import { scaleLinear } from 'd3-scale';
import { componentsAt } from './timeline.js';

const kWidthPx = 900;
const kPanelPx = 44;
const kGapPx = 16;
const kLeftPx = 110;
const kPanels = [
  { key: 'components', label: 'components' },
  { key: 'stf', label: 'STF (max, mean)' },
  { key: 'lag', label: 'lag max ms' },
];

export class TimelineChart {
  constructor(svgElement, note) {
    this.svg = select(svgElement)
      .attr('width', kWidthPx)
      .attr('height', kPanels.length * (kPanelPx + kGapPx));
    this.note = select(note);
  }

  // `connectivity`, `timing`: as /api/timeline; `endS`: the time axis' end; `cursorS`: the
  // time shown; `timingSecond`: the second whose timing the note gives; `names[i]`: robot i.
  draw(connectivity, timing, endS, cursorS, timingSecond, names) {
    const x = scaleLinear().domain([0, Math.max(endS, 1)]).range([kLeftPx, kWidthPx - 4]);
    const maxComponents = Math.max(1, ...connectivity.map((c) => c[1]));
    const maxStf = Math.max(1, ...timing.map((s) => s[3]));
    const maxLag = Math.max(1, ...timing.map((s) => s[4]));
    const series = {
      components: { points: steps(connectivity.map((c) => [c[0], c[1]]), endS), top: maxComponents },
      stf: { points: steps(timing.map((s) => [s[0], s[3]]), endS),
        extra: steps(timing.map((s) => [s[0], s[2]]), endS), top: maxStf },
      lag: { points: steps(timing.map((s) => [s[0], s[4]]), endS), top: maxLag },
    };
    const panels = this.svg.selectAll('g.panel').data(kPanels, (p) => p.key).join((enter) => {
      const g = enter.append('g').attr('class', (p) => `panel ${p.key}`);
      g.append('text').attr('class', 'panel-label').attr('x', 0).attr('y', kPanelPx / 2)
        .text((p) => p.label);
      g.append('text').attr('class', 'panel-top').attr('x', kLeftPx - 6).attr('y', 9);
      g.append('line').attr('class', 'axis').attr('x1', kLeftPx).attr('y1', kPanelPx)
        .attr('y2', kPanelPx);
      g.append('polyline').attr('class', 'extra');
      g.append('polyline').attr('class', 'series');
      return g;
    });
    panels.attr('transform', (_, i) => `translate(0, ${i * (kPanelPx + kGapPx) + 4})`);
    panels.select('line.axis').attr('x2', kWidthPx - 4);
    panels.select('text.panel-top').text((p) => Number(series[p.key].top.toPrecision(3)));
    const line = (p, points) => {
      const y = scaleLinear().domain([0, series[p.key].top]).range([kPanelPx, 0]);
      return points.map(([t, v]) => `${x(t)},${y(v)}`).join(' ');
    };
    panels.select('polyline.series').attr('points', (p) => line(p, series[p.key].points));
    panels.select('polyline.extra').attr('points', (p) => line(p, series[p.key].extra ?? []));
    this.svg.selectAll('line.cursor').data([cursorS]).join('line').attr('class', 'cursor')
      .attr('x1', x(cursorS)).attr('x2', x(cursorS)).attr('y1', 0)
      .attr('y2', kPanels.length * (kPanelPx + kGapPx));

    const now = componentsAt(connectivity, cursorS);
    const second = timing.find((s) => s[0] === timingSecond);
    const data = this.svg.node().dataset;
    data.maxComponents = maxComponents;
    data.changes = connectivity.length;
    data.cursorTimeS = cursorS;
    data.components = now ? now[1] : '';
    data.componentsTimeS = now ? now[0] : '';
    data.componentOf = now ? now[2].join(',') : '';
    data.timingSecond = second ? second[0] : '';
    data.iterations = second ? second[1] : '';
    data.stfMean = second ? second[2] : '';
    data.stfMax = second ? second[3] : '';
    data.lagMaxMs = second ? second[4] : '';
    const groups = now ? membersOf(now[2]).map((m) => m.map((i) => names(i)).join(' ')) : [];
    this.note.text((now ? `${now[1]} component${now[1] > 1 ? 's' : ''}: ${groups.join(' | ')}` :
      'no connectivity sample yet') + (second ? `; second ${second[0]}: STF mean ` +
      `${second[2].toFixed(3)}, max ${second[3].toFixed(3)}; lag max ${second[4].toFixed(1)} ms` : ''));
  }
}

// Points of a step line through `values` ([time, value], time ascending) until `endS`.
function steps(values, endS) {
  const points = [];
  values.forEach(([t, v], i) => {
    if (i > 0) points.push([t, values[i - 1][1]]);
    points.push([t, v]);
  });
  if (values.length > 0) points.push([Math.max(endS, values[values.length - 1][0]), values[values.length - 1][1]]);
  return points;
}

// Robot indices grouped by component, in the order of each component's smallest index.
function membersOf(componentOf) {
  const groups = new Map();
  componentOf.forEach((c, i) => {
    if (!groups.has(c)) groups.set(c, []);
    groups.get(c).push(i);
  });
  return [...groups.values()];
}
