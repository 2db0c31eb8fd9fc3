// What the GCS relay heard of each vehicle (/api/gcs in a replay, /api/live's "gcs" live;
// docs/view-reference.md, "GCS relay"), per robot, and how the table and the map say it.

// `vehicles` ([{robot, system_id, mode, armed, messages, sequence_gaps, loss}]) as a list by
// robot index, null where no vehicle came from that robot. A robot that sent more than one
// system id shows the first.
export function vehiclesByRobot(vehicles, robotCount) {
  const byRobot = new Array(robotCount).fill(null);
  for (const vehicle of vehicles ?? []) {
    if (vehicle.robot !== null && vehicle.robot >= 0 && vehicle.robot < robotCount &&
        byRobot[vehicle.robot] === null) {
      byRobot[vehicle.robot] = vehicle;
    }
  }
  return byRobot;
}

export const gcsModeText = (v) => (v ? (v.mode ?? 'no heartbeat') : '');
export const armedText = (v) => (v && v.armed !== null ? (v.armed ? 'armed' : 'disarmed') : '');
// MAVLink loss: frames missing by sequence number over those heard and missing.
export const lossText = (v) => (v && v.loss !== null ? `${(v.loss * 100).toFixed(1)} %` : '');

// The map's second label line: "GUIDED · armed · 2.5 % lost"; '' for a robot without a vehicle.
export function statusLine(v) {
  if (!v) return '';
  const parts = [gcsModeText(v)];
  if (v.armed !== null) parts.push(armedText(v));
  if (v.loss !== null) parts.push(`${lossText(v)} lost`);
  return parts.join(' · ');
}
