// The server's JSON endpoints (docs/view.md, "Endpoints").
async function getJson(path) {
  const response = await fetch(path);
  if (!response.ok) throw new Error(`${path}: ${response.status} ${await response.text()}`);
  return response.json();
}

export const loadRun = () => getJson('api/run');
export const loadTrajectories = () => getJson('api/trajectories');
export const loadLinks = () => getJson('api/links');
export const loadLive = () => getJson('api/live');
export const loadTimeline = () => getJson('api/timeline');
export const loadModes = () => getJson('api/modes');
export const loadGcs = () => getJson('api/gcs');

// Rows of losses.csv.gz for frames by `from` that reached `station` in [endS - 1 s, endS).
export const loadFrames = (from, station, endS) =>
  getJson(`api/frames?from=${from}&to=${station}&t=${endS}&window=1`);

// A sweep's folder: its points.csv and summary.csv as text (`sitlnet view SWEEP_DIR`).
export const loadSweep = () => getJson('api/sweep');
