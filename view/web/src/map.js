// The map from above: obstacles, trails, links and robots, in an SVG whose scale the page
// exposes (data-px-per-m, data-min-x-m, data-max-y-m on the svg; data-x-m, data-y-m on each
// robot) so a test can check where things are drawn.
import { pointer, select } from 'd3-selection';
import { scaleLinear } from 'd3-scale';
import { setChanged, setTextChanged } from './dom.js';

const kMaxWidthPx = 900;
const kMaxHeightPx = 640;
const kMarginM = 3;
const kLinkOffsetPx = 2.5;  // A->B and B->A drawn side by side, both clickable.
const kLinkHitPx = 4;  // A click this close to a link selects it (the nearest).

export const ratioColour = scaleLinear().domain([0, 0.5, 1]).range(['#d62728', '#ff9f1a', '#2ca02c']);

export const robotColour = (index) => `hsl(${(index * 137.5) % 360}, 65%, 45%)`;

// The corners of an obstacle's footprint, as scenario.proto's Obstacle defines it.
function corners(obstacle) {
  const yaw = (obstacle.yaw_deg * Math.PI) / 180;
  const hx = obstacle.size_m[0] / 2;
  const hy = obstacle.size_m[1] / 2;
  return [[-hx, -hy], [hx, -hy], [hx, hy], [-hx, hy]].map(([cx, cy]) => [
    obstacle.center_m[0] + cx * Math.cos(yaw) - cy * Math.sin(yaw),
    obstacle.center_m[1] + cx * Math.sin(yaw) + cy * Math.cos(yaw),
  ]);
}

// The points [x, y] a map of `run` must show: its obstacles' corners and `positions`.
export function pointsToShow(run, positions) {
  return run.obstacles.flatMap(corners).concat(positions);
}

export class MapView {
  // Scaled to show `points` ([x, y] in metres) with a margin.
  constructor(svgElement, run, points, onLinkClick) {
    if (points.length === 0) points = [[0, 0]];
    const xs = points.map((p) => p[0]);
    const ys = points.map((p) => p[1]);
    this.minX = Math.min(...xs) - kMarginM;
    this.maxY = Math.max(...ys) + kMarginM;
    const widthM = Math.max(...xs) + kMarginM - this.minX;
    const heightM = this.maxY - (Math.min(...ys) - kMarginM);
    this.pxPerM = Math.min(kMaxWidthPx / widthM, kMaxHeightPx / heightM);
    this.bounds = [this.minX, this.minX + widthM, this.maxY - heightM, this.maxY];
    select(svgElement).selectAll('*').remove();
    this.svg = select(svgElement)
      .attr('width', Math.ceil(widthM * this.pxPerM))
      .attr('height', Math.ceil(heightM * this.pxPerM))
      .attr('data-px-per-m', this.pxPerM)
      .attr('data-min-x-m', this.minX)
      .attr('data-max-y-m', this.maxY);
    this.onLinkClick = onLinkClick;
    this.selected = null;
    this.drawnLinks = [];  // [{ link, ends }] as drawn, for clicks near a line.
    this.svg.on('click', (event) => this.clickNear(event));

    this.svg.append('g').attr('class', 'obstacles').selectAll('polygon').data(run.obstacles)
      .join('polygon').attr('class', 'obstacle')
      .attr('points', (o) => corners(o).map(([x, y]) => `${this.px(x)},${this.py(y)}`).join(' '))
      .append('title').text((o) => o.name);
    this.trails = this.svg.append('g').attr('class', 'trails');
    this.links = this.svg.append('g').attr('class', 'links');
    this.robots = this.svg.append('g').attr('class', 'robots');
  }

  // Whether every point [x, y] is inside the map.
  shows(points) {
    const [x0, x1, y0, y1] = this.bounds;
    return points.every(([x, y]) => x >= x0 && x <= x1 && y >= y0 && y <= y1);
  }

  px(xM) { return (xM - this.minX) * this.pxPerM; }
  py(yM) { return (this.maxY - yM) * this.pxPerM; }

  // `positions[i]`: robot i's sample [t, x, y, z, speed] or null; `trails[i]`: its samples so
  // far; `links`: links.csv rows of the second shown. Attributes are written only where they
  // changed: with 64 robots, a thousand links and 64 trails, writing them all was most of the
  // page's work.
  draw(run, positions, trails, links) {
    this.trails.selectAll('polyline').data(trails).join('polyline').attr('class', 'trail')
      .attr('stroke', (_, i) => robotColour(i))
      .each((samples, i, nodes) => setChanged(nodes[i], 'points',
        samples.map((s) => `${this.px(s[1])},${this.py(s[2])}`).join(' ')));
    this.drawLinks(positions, links);
    const robots = run.robots.filter((r) => positions[r.index]);
    const groups = this.robots.selectAll('g.robot-group').data(robots, (r) => r.index)
      .join((enter) => {
        const g = enter.append('g').attr('class', 'robot-group');
        g.append('circle').attr('class', 'robot').attr('r', 5)
          .attr('fill', (r) => robotColour(r.index)).attr('data-robot', (r) => r.index);
        g.append('text').attr('class', 'robot-label').attr('dx', 7).attr('dy', -6)
          .text((r) => r.name);
        return g;
      });
    groups.each((r, i, nodes) => {
      const [t, x, y] = positions[r.index];
      const [circle, label] = nodes[i].childNodes;
      setChanged(circle, 'cx', this.px(x));
      setChanged(circle, 'cy', this.py(y));
      setChanged(circle, 'data-x-m', x);
      setChanged(circle, 'data-y-m', y);
      setChanged(circle, 'data-time-s', t);
      setChanged(label, 'x', this.px(x));
      setChanged(label, 'y', this.py(y));
    });
  }

  // One line per link (line.link, keyed by its ends), drawn 2.5 px to the right of A -> B.
  drawLinks(positions, links) {
    const drawn = links.filter((l) => l[2] >= 0 && l[1] !== l[2] && positions[l[1]] && positions[l[2]]);
    const ends = (l) => {
      const [x1, y1] = [this.px(positions[l[1]][1]), this.py(positions[l[1]][2])];
      const [x2, y2] = [this.px(positions[l[2]][1]), this.py(positions[l[2]][2])];
      const length = Math.hypot(x2 - x1, y2 - y1) || 1;
      const [ox, oy] = [(-(y2 - y1) / length) * kLinkOffsetPx, ((x2 - x1) / length) * kLinkOffsetPx];
      return { x1: x1 + ox, y1: y1 + oy, x2: x2 + ox, y2: y2 + oy };
    };
    this.drawnLinks = drawn.map((link) => ({ link, ends: ends(link) }));
    this.links.selectAll('line.link').data(this.drawnLinks, (d) => linkKey(d.link))
      .join((enter) => enter.append('line').attr('class', 'link')
        .attr('data-from', (d) => d.link[1]).attr('data-to', (d) => d.link[2])
        .call((line) => line.append('title')))
      .each((d, i, nodes) => {
        const line = nodes[i];
        const l = d.link;
        for (const end of ['x1', 'y1', 'x2', 'y2']) setChanged(line, end, d.ends[end].toFixed(2));
        setChanged(line, 'class', this.lineClass(l));
        setChanged(line, 'stroke', l[5] === null ? null : ratioColour(l[5]));
        setChanged(line, 'data-ratio', l[5]);
        setChanged(line, 'data-frames', l[3]);
        setChanged(line, 'data-delivered', l[4]);
        setTextChanged(line.firstChild, `${l[1]} -> ${l[2]}: ${l[4]}/${l[3]} delivered` +
          (l[6] !== 'none' ? `, mostly ${l[6]} (${l[7]})` : ''));
      });
  }

  // A click on a link, or within kLinkHitPx of the nearest one, selects it.
  clickNear(event) {
    let best = event.target.__data__?.link ? event.target.__data__ : null;
    if (!best) {
      const [x, y] = pointer(event, this.svg.node());
      let bestPx = kLinkHitPx;
      for (const d of this.drawnLinks) {
        const distancePx = distanceToSegment(x, y, d.ends);
        if (distancePx <= bestPx) [best, bestPx] = [d, distancePx];
      }
    }
    if (!best) return;
    this.selected = linkKey(best.link);
    this.onLinkClick(best.link[1], best.link[2]);
    this.links.selectAll('line.link').each((d, i, nodes) =>
      setChanged(nodes[i], 'class', this.lineClass(d.link)));
  }

  lineClass(l) {
    return `link${l[5] === null ? ' drops-only' : ''}${linkKey(l) === this.selected ? ' selected' : ''}`;
  }
}

const linkKey = (l) => `${l[1]}-${l[2]}`;

// Distance in px from (x, y) to the segment `ends` ({x1, y1, x2, y2}).
function distanceToSegment(x, y, { x1, y1, x2, y2 }) {
  const [dx, dy] = [x2 - x1, y2 - y1];
  const lengthSquared = dx * dx + dy * dy;
  const along = lengthSquared > 0 ? Math.max(0, Math.min(1, ((x - x1) * dx + (y - y1) * dy) / lengthSquared)) : 0;
  return Math.hypot(x - (x1 + along * dx), y - (y1 + along * dy));
}
