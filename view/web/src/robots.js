// The robots' table: position, altitude and speed at the time shown.
import { select } from 'd3-selection';

// `positions[i]`: robot i's [t, x, y, z, speed], or null (not drawn).
export function drawRobotTable(run, positions) {
  select('#robots tbody').selectAll('tr').data(run.robots.filter((r) => positions[r.index])).join('tr')
    .selectAll('td')
    .data((r) => {
      const p = positions[r.index];
      return [r.name, p[1].toFixed(2), p[2].toFixed(2), p[3].toFixed(2), p[4].toFixed(2)];
    })
    .join('td').text((c) => c);
}
