// The robots' table: position, altitude, speed, connectivity component and autopilot mode at
// the time shown.
import { select } from 'd3-selection';

// What the page can say of a robot's autopilot mode (docs/view-reference.md, "Autopilot
// mode"): sitlnet reads no mode from PX4's or ArduPilot's simulator interface.
const modeOf = (robot) => (robot.autopilot ? 'unknown' : 'none');

// `positions[i]`: robot i's [t, x, y, z, speed], or null (not drawn); `componentOf[i]`: its
// component's smallest robot index, or undefined.
export function drawRobotTable(run, positions, componentOf) {
  const name = (i) => run.robots[i]?.name ?? String(i);
  select('#robots tbody').selectAll('tr').data(run.robots.filter((r) => positions[r.index])).join('tr')
    .selectAll('td')
    .data((r) => {
      const p = positions[r.index];
      const component = componentOf?.[r.index];
      return [r.name, p[1].toFixed(2), p[2].toFixed(2), p[3].toFixed(2), p[4].toFixed(2),
        component === undefined ? '' : `with ${name(component)}`, modeOf(r)];
    })
    .join('td').text((c) => c);
}
