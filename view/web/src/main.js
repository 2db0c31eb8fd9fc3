// The page of `sitlnet view`: loads the run, draws it at the slider's time, lists a clicked
// link's frames; or, for `sitlnet run --view`, follows the run (live.js). document.body's
// data-ready is "true" once the first drawing is done.
import { select } from 'd3-selection';
import {
  loadFrames, loadGcs, loadLinks, loadModes, loadRun, loadTimeline, loadTrajectories,
} from './api.js';
import { TimelineChart } from './chart.js';
import { FrameList } from './frames.js';
import { drawRobotTable } from './robots.js';
import { runLive } from './live.js';
import { statusLine, vehiclesByRobot } from './gcs.js';
import { MapView, bindMapButtons, pointsToShow, ratioColour } from './map.js';
import {
  componentsAt, linkSecondAt, linksBySecond, modesAt, modesByRobot, sampleAt, trailUntil,
} from './timeline.js';

function drawLegend() {
  const legend = select('#legend');
  for (const [ratio, text] of [[0, '0'], [0.5, '0.5'], [1, '1']]) {
    legend.append('span').attr('class', 'swatch').style('background', ratioColour(ratio));
    legend.append('span').text(text);
  }
  legend.append('span').attr('class', 'swatch').style('background', '#888');
  legend.append('span').text('only sender drops');
}

async function replay(run) {
  const [trajectories, links, timeline, modes, gcs] = await Promise.all(
    [loadTrajectories(), loadLinks(), loadTimeline(), loadModes(), loadGcs()]);
  // The relay's counts at the run's end (summary.json): the same at every slider time.
  const vehicles = vehiclesByRobot(gcs.vehicles, run.robots.length);
  const statuses = vehicles.map(statusLine);
  const bySecond = linksBySecond(links.links);
  const modesOfRobots = modesByRobot(modes.modes, run.robots.length);
  const robotName = (index) => run.robots[index]?.name ?? String(index);
  const frames = new FrameList('#frames', '#frames-title', '#frames-note', run.loss_columns);
  const slider = document.getElementById('time');
  slider.max = run.end_s;
  const currentTime = () => Number(slider.value);

  let frameRequest = 0;  // Only the answer to the latest click is shown.
  const showFrames = async (from, station) => {
    const request = ++frameRequest;
    const answer = await loadFrames(from, station, linkSecondAt(currentTime()) + 1);
    if (request === frameRequest) frames.show(answer, robotName);
  };
  const everywhere = trajectories.robots.flatMap((samples) => samples.map((s) => [s[1], s[2]]));
  const map = new MapView(document.getElementById('map'), run, pointsToShow(run, everywhere),
    showFrames);
  bindMapButtons(() => map);
  const chart = new TimelineChart(document.getElementById('timeline'), '#timeline-note');

  const draw = () => {
    const t = currentTime();
    select('#time-label').text(`${t.toFixed(1)} s`);
    const positions = trajectories.robots.map((samples) => sampleAt(samples, t));
    const trails = trajectories.robots.map((samples) => trailUntil(samples, t));
    map.draw(run, positions, trails, bySecond.get(linkSecondAt(t)) ?? [], statuses);
    drawRobotTable(run, positions, componentsAt(timeline.connectivity, t)?.[2],
      modesAt(modesOfRobots, t), vehicles);
    chart.draw(timeline.connectivity, timeline.timing, run.end_s, t, linkSecondAt(t), robotName);
  };
  slider.addEventListener('input', () => {
    frameRequest++;
    map.selected = null;
    frames.clear();
    draw();
  });
  draw();
  document.body.dataset.ready = 'true';
}

async function main() {
  const run = await loadRun();
  select('#title').text(`sitlnet ${run.live ? 'run (live)' : 'view'}: ${run.name}`);
  document.title = `sitlnet: ${run.name}`;
  drawLegend();
  await (run.live ? runLive(run) : replay(run));
}

main().catch((error) => {
  console.error(error);
  select('#title').text(`sitlnet view: ${error.message}`);
});
