// The robots' table: position, altitude, speed, connectivity component and autopilot mode at
// the time shown.
import { select } from 'd3-selection';
import { setChanged, setTextChanged } from './dom.js';

// What the page says of a robot's autopilot mode (docs/view-reference.md, "Autopilot mode"):
// the last one its HEARTBEATs reported over the radio; else `unknown` for a PX4 or ArduPilot
// robot, `none` for another.
const modeText = (robot, mode) => mode ?? (robot.autopilot ? 'unknown' : 'none');

// `positions[i]`: robot i's [t, x, y, z, speed], or null (not drawn); `componentOf[i]`: its
// component's smallest robot index, or undefined; `modes[i]`: its autopilot's mode, or null.
export function drawRobotTable(run, positions, componentOf, modes) {
  const name = (i) => run.robots[i]?.name ?? String(i);
  select('#robots tbody').selectAll('tr')
    .data(run.robots.filter((r) => positions[r.index]), (r) => r.index).join('tr')
    .each((r, i, rows) => {
      setChanged(rows[i], 'data-robot', r.index);
      setChanged(rows[i], 'data-mode', modeText(r, modes?.[r.index]));
    })
    .selectAll('td')
    .data((r) => {
      const p = positions[r.index];
      const component = componentOf?.[r.index];
      return [r.name, p[1].toFixed(2), p[2].toFixed(2), p[3].toFixed(2), p[4].toFixed(2),
        component === undefined ? '' : `with ${name(component)}`, modeText(r, modes?.[r.index])];
    })
    .join('td').each((c, i, cells) => setTextChanged(cells[i], c));
}
