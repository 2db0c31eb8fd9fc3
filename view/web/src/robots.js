// The robots' table: position, altitude, speed, connectivity component and autopilot mode at
// the time shown, and what the GCS relay heard of the robot's vehicle (shown once a run has one).
import { select } from 'd3-selection';
import { setChanged, setTextChanged } from './dom.js';
import { armedText, gcsModeText, lossText } from './gcs.js';

// What the page says of a robot's autopilot mode (docs/view-reference.md, "Autopilot mode"):
// the last one its HEARTBEATs reported over the radio; else `unknown` for a PX4 or ArduPilot
// robot, `none` for another.
const modeText = (robot, mode) => mode ?? (robot.autopilot ? 'unknown' : 'none');

// `positions[i]`: robot i's [t, x, y, z, speed], or null (not drawn); `componentOf[i]`: its
// component's smallest robot index, or undefined; `modes[i]`: its autopilot's mode, or null;
// `vehicles[i]`: what the GCS relay heard of it (gcs.js), or null.
export function drawRobotTable(run, positions, componentOf, modes, vehicles = []) {
  const name = (i) => run.robots[i]?.name ?? String(i);
  const withGcs = vehicles.some(Boolean);
  select('#robots').classed('with-gcs', withGcs);
  select('#robots tbody').selectAll('tr')
    .data(run.robots.filter((r) => positions[r.index]), (r) => r.index).join('tr')
    .each((r, i, rows) => {
      setChanged(rows[i], 'data-robot', r.index);
      setChanged(rows[i], 'data-mode', modeText(r, modes?.[r.index]));
      const v = vehicles[r.index];
      setChanged(rows[i], 'data-system-id', v?.system_id);
      setChanged(rows[i], 'data-gcs-mode', v ? gcsModeText(v) : null);
      setChanged(rows[i], 'data-armed', v && v.armed !== null ? v.armed : null);
      setChanged(rows[i], 'data-loss', v && v.loss !== null ? v.loss : null);
    })
    .selectAll('td')
    .data((r) => {
      const p = positions[r.index];
      const component = componentOf?.[r.index];
      return [r.name, p[1].toFixed(2), p[2].toFixed(2), p[3].toFixed(2), p[4].toFixed(2),
        component === undefined ? '' : `with ${name(component)}`, modeText(r, modes?.[r.index])]
        .concat(withGcs ? [gcsModeText(vehicles[r.index]), armedText(vehicles[r.index]),
          lossText(vehicles[r.index])] : []);
    })
    .join('td').each((c, i, cells) => setTextChanged(cells[i], c));
}
