// The map from above: obstacles, trails, links and robots, in an SVG whose scale the page
// exposes (data-px-per-m, data-min-x-m, data-max-y-m on the svg; data-x-m, data-y-m on each
// robot) so a test can check where things are drawn. The wheel zooms about the pointer, a drag
// pans, fitFleet() frames the robots and fitAll() the whole field; each redraws in px, so line
// widths, link offsets and labels keep their size. Labels do not overlap (labels.js).
import { pointer, select } from 'd3-selection';
import { scaleLinear } from 'd3-scale';
import { setChanged, setTextChanged } from './dom.js';
import { placeLabels } from './labels.js';

const kMaxWidthPx = 900;
const kMaxHeightPx = 640;
const kMinHeightPx = 480;  // A wide field still leaves room to zoom in on the fleet.
const kMarginM = 3;
const kLinkOffsetPx = 2.5;  // A->B and B->A drawn side by side, both clickable.
const kLinkHitPx = 4;  // A click this close to a link selects it (the nearest).
const kDragPx = 3;  // A press that moves farther than this pans, and is no click.
const kWheelZoomPerPx = 0.002;  // exp(-deltaY * this): about 1.2 per notch of 100 px.
const kFleetMarginM = 5;  // Fit the fleet: at least this much room around the robots,
const kFleetMarginShare = 0.15;  // or this share of their spread, whichever is larger.
const kLabelSizesKept = 1024;  // Label texts whose measured size is kept.

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
    this.widthPx = Math.ceil(widthM * this.pxPerM);
    this.heightPx = Math.max(Math.ceil(heightM * this.pxPerM), kMinHeightPx);
    // Centred vertically when the svg is taller than the field.
    this.maxY += (this.heightPx / this.pxPerM - heightM) / 2;
    this.whole = { minX: this.minX, maxY: this.maxY, pxPerM: this.pxPerM };
    this.userMoved = false;  // Zoomed, panned or fitted by the user: live keeps this view.
    select(svgElement).selectAll('*').remove();
    this.svg = select(svgElement)
      .attr('width', this.widthPx)
      .attr('height', this.heightPx);
    this.run = run;
    this.onLinkClick = onLinkClick;
    this.selected = null;
    this.drawnLinks = [];  // [{ link, ends }] as drawn, for clicks near a line.
    this.last = null;  // The latest draw's arguments, drawn again when the view moves.
    this.labelSizes = new Map();  // Label text -> its {width, height, x, y} box at the origin.
    this.svg.on('click', (event) => this.clickNear(event));
    this.svg.on('wheel', (event) => this.zoomAt(event), { passive: false });
    this.svg.on('pointerdown', (event) => this.pressed(event));
    this.svg.on('pointermove', (event) => this.dragged(event));
    this.svg.on('pointerup pointercancel', (event) => this.released(event));

    this.obstacles = this.svg.append('g').attr('class', 'obstacles');
    this.obstacles.selectAll('polygon').data(run.obstacles).join('polygon').attr('class', 'obstacle')
      .append('title').text((o) => o.name);
    this.trails = this.svg.append('g').attr('class', 'trails');
    this.links = this.svg.append('g').attr('class', 'links');
    this.robots = this.svg.append('g').attr('class', 'robots');
    this.setView(this.whole);
    this.userMoved = false;
  }

  // Draws everything at a new scale: `minX`, `maxY` (m) at the svg's top-left, `pxPerM`.
  setView({ minX, maxY, pxPerM }) {
    [this.minX, this.maxY, this.pxPerM] = [minX, maxY, pxPerM];
    this.userMoved = true;
    this.svg.attr('data-px-per-m', pxPerM).attr('data-min-x-m', minX).attr('data-max-y-m', maxY);
    this.obstacles.selectAll('polygon')
      .attr('points', (o) => corners(o).map(([x, y]) => `${this.px(x)},${this.py(y)}`).join(' '));
    if (this.last) this.draw(...this.last);
  }

  // Frames the metre box [x0, x1] x [y0, y1], centred, as large as the svg allows.
  fitBox(x0, x1, y0, y1) {
    const pxPerM = Math.min(this.widthPx / Math.max(x1 - x0, 1e-3), this.heightPx / Math.max(y1 - y0, 1e-3));
    this.setView({
      minX: (x0 + x1) / 2 - this.widthPx / 2 / pxPerM,
      maxY: (y0 + y1) / 2 + this.heightPx / 2 / pxPerM,
      pxPerM,
    });
  }

  // Frames the robots drawn last: their bounding box with a margin of kFleetMarginM or
  // kFleetMarginShare of its larger side, whichever is larger.
  fitFleet() {
    const here = (this.last?.[1] ?? []).filter(Boolean);
    if (here.length === 0) return;
    const xs = here.map((p) => p[1]);
    const ys = here.map((p) => p[2]);
    const [x0, x1, y0, y1] = [Math.min(...xs), Math.max(...xs), Math.min(...ys), Math.max(...ys)];
    const margin = Math.max(kFleetMarginM, kFleetMarginShare * Math.max(x1 - x0, y1 - y0));
    this.fitBox(x0 - margin, x1 + margin, y0 - margin, y1 + margin);
  }

  // Back to the whole field, as first drawn; live, the page follows the fleet again.
  fitAll() {
    this.setView(this.whole);
    this.userMoved = false;
  }

  // The wheel: zoom about the pointer, which keeps the point under it.
  zoomAt(event) {
    event.preventDefault();
    const [x, y] = pointer(event, this.svg.node());
    const factor = Math.exp(-event.deltaY * kWheelZoomPerPx);
    const [xM, yM] = [this.minX + x / this.pxPerM, this.maxY - y / this.pxPerM];
    const pxPerM = this.pxPerM * factor;
    this.setView({ minX: xM - x / pxPerM, maxY: yM + y / pxPerM, pxPerM });
  }

  // A press, a move farther than kDragPx and a release pan the map; the click that follows is
  // then no link's.
  pressed(event) {
    if (event.button !== 0) return;
    this.drag = { x: event.clientX, y: event.clientY, minX: this.minX, maxY: this.maxY, moved: false };
  }

  dragged(event) {
    if (!this.drag) return;
    const [dx, dy] = [event.clientX - this.drag.x, event.clientY - this.drag.y];
    if (!this.drag.moved && Math.hypot(dx, dy) <= kDragPx) return;
    if (!this.drag.moved) {
      this.drag.moved = true;
      this.svg.node().setPointerCapture?.(event.pointerId);
      this.svg.classed('panning', true);
    }
    this.setView({ minX: this.drag.minX - dx / this.pxPerM, maxY: this.drag.maxY + dy / this.pxPerM, pxPerM: this.pxPerM });
  }

  released() {
    this.justPanned = this.drag?.moved ?? false;
    this.drag = null;
    this.svg.classed('panning', false);
  }

  // Whether every point [x, y] is inside the map.
  shows(points) {
    const [x0, x1, y0, y1] = this.bounds;
    return points.every(([x, y]) => x >= x0 && x <= x1 && y >= y0 && y <= y1);
  }

  px(xM) { return (xM - this.minX) * this.pxPerM; }
  py(yM) { return (this.maxY - yM) * this.pxPerM; }

  // `positions[i]`: robot i's sample [t, x, y, z, speed] or null; `trails[i]`: its samples so
  // far; `links`: links.csv rows of the second shown; `statuses[i]`: the second line of its
  // label ('' or absent: none). Attributes are written only where they changed: with 64 robots,
  // a thousand links and 64 trails, writing them all was most of the page's work.
  draw(run, positions, trails, links, statuses = []) {
    this.last = [run, positions, trails, links, statuses];
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
        const label = g.append('text').attr('class', 'robot-label').attr('data-robot', (r) => r.index);
        label.append('tspan').attr('class', 'name').attr('x', 0).text((r) => r.name);
        label.append('tspan').attr('class', 'status').attr('x', 0).attr('dy', '1.2em');
        return g;
      });
    const anchors = [];
    const sizes = [];
    const labels = [];
    groups.each((r, i, nodes) => {
      const [t, x, y] = positions[r.index];
      const [circle, label] = nodes[i].childNodes;
      setChanged(circle, 'cx', this.px(x));
      setChanged(circle, 'cy', this.py(y));
      setChanged(circle, 'data-x-m', x);
      setChanged(circle, 'data-y-m', y);
      setChanged(circle, 'data-time-s', t);
      const status = statuses[r.index] ?? '';
      setTextChanged(label.lastChild, status);
      setChanged(label, 'data-status', status);
      anchors.push({ x: this.px(x), y: this.py(y) });
      sizes.push(this.labelSize(label, `${r.name}\n${status}`));
      labels.push(label);
    });
    placeLabels(anchors, sizes).forEach((box, i) => {
      const size = sizes[i];
      setChanged(labels[i], 'transform',
        `translate(${(box.x - size.x).toFixed(1)},${(box.y - size.y).toFixed(1)})`);
    });
  }

  // The box of `label` (a text at the origin) for its text `key`, measured once per text: the
  // browser lays text out only when a label's text changes.
  labelSize(label, key) {
    let size = this.labelSizes.get(key);
    if (!size) {
      // Live, a loss in a label changes often: forget old texts rather than grow without end.
      if (this.labelSizes.size >= kLabelSizesKept) this.labelSizes.clear();
      const saved = label.getAttribute('transform');
      label.removeAttribute('transform');
      const box = label.getBBox();
      if (saved !== null) label.setAttribute('transform', saved);
      size = { x: box.x, y: box.y, width: box.width, height: box.height };
      this.labelSizes.set(key, size);
    }
    return size;
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
    if (this.justPanned) {
      this.justPanned = false;
      return;
    }
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

// The map's buttons: #fit-fleet and #fit-all act on the map `currentMap()` returns (live makes
// a new one when the fleet leaves it).
export function bindMapButtons(currentMap) {
  document.getElementById('fit-fleet').addEventListener('click', () => currentMap()?.fitFleet());
  document.getElementById('fit-all').addEventListener('click', () => currentMap()?.fitAll());
}

// Distance in px from (x, y) to the segment `ends` ({x1, y1, x2, y2}).
function distanceToSegment(x, y, { x1, y1, x2, y2 }) {
  const [dx, dy] = [x2 - x1, y2 - y1];
  const lengthSquared = dx * dx + dy * dy;
  const along = lengthSquared > 0 ? Math.max(0, Math.min(1, ((x - x1) * dx + (y - y1) * dy) / lengthSquared)) : 0;
  return Math.hypot(x - (x1 + along * dx), y - (y1 + along * dy));
}
