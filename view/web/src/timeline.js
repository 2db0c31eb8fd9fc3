// What the run looked like at a time: each robot's last sample, the links of a second, the
// connectivity components.

// The last sample at or before `timeS` ([time_s, x, y, z, speed]), or the first one.
export function sampleAt(samples, timeS) {
  let low = 0;
  let high = samples.length - 1;
  if (high < 0) return null;
  // Sample times are written in milliseconds; a small margin keeps 0.3 from missing 0.30000001.
  const t = timeS + 1e-6;
  if (samples[0][0] > t) return samples[0];
  while (low < high) {
    const middle = (low + high + 1) >> 1;
    if (samples[middle][0] <= t) low = middle;
    else high = middle - 1;
  }
  return samples[low];
}

// The last change of components at or before `timeS` ([time_s, components, component_of]), or
// null before the first.
export function componentsAt(changes, timeS) {
  const change = sampleAt(changes, timeS);
  return change && change[0] <= timeS + 1e-6 ? change : null;
}

// The samples up to `timeS`: a robot's trail.
export function trailUntil(samples, timeS) {
  const last = sampleAt(samples, timeS);
  return last ? samples.slice(0, samples.indexOf(last) + 1) : [];
}

// The second of links.csv the map colours at `timeS`: the last whole second before it.
export const linkSecondAt = (timeS) => Math.floor(timeS + 1e-6) - 1;

// links.csv rows grouped by second: Map second -> rows.
export function linksBySecond(rows) {
  const bySecond = new Map();
  for (const row of rows) {
    if (!bySecond.has(row[0])) bySecond.set(row[0], []);
    bySecond.get(row[0]).push(row);
  }
  return bySecond;
}

// Autopilot mode changes ([time_s, robot, mode], in time order) per robot: an array by robot
// index of [time_s, mode] lists.
export function modesByRobot(changes, robotCount) {
  const byRobot = Array.from({ length: robotCount }, () => []);
  for (const [t, robot, mode] of changes) byRobot[robot]?.push([t, mode]);
  return byRobot;
}

// Each robot's mode at `timeS` (its last change at or before it), or null before the first.
export const modesAt = (byRobot, timeS) =>
  byRobot.map((changes) => componentsAt(changes, timeS)?.[1] ?? null);
