// The live page of `sitlnet run --view`: asks for /api/live every kPollMs (one request at a
// time, so a slow page never piles requests up), draws the latest poses, trails and the last
// whole second's links, and the timeline (components, STF, lag) so far. Clicking a link shows its
// counts (the frame list is the replay's).
import { select } from 'd3-selection';
import { loadLive } from './api.js';
import { TimelineChart } from './chart.js';
import { statusLine, vehiclesByRobot } from './gcs.js';
import { MapView, bindMapButtons, pointsToShow } from './map.js';
import { drawRobotTable } from './robots.js';

const kPollMs = 500;
const kMarginPoints = [[-20, -20], [20, 20]];  // Room to fly before the map rescales.

function showLink(run, link) {
  const name = (i) => run.robots[i]?.name ?? String(i);
  select('#frames-title').text(`Link ${name(link[1])} -> ${name(link[2])}, second ${link[0]}`);
  select('#frames-note').text(`${link[4]} of ${link[3]} DATA frames decoded` +
    (link[6] !== 'none' ? `; most lost: ${link[6]} (${link[7]})` : '') +
    '. Each frame and its cause: replay the run folder with sitlnet view.');
}

export async function runLive(run) {
  select('#time').property('disabled', true);
  let map = null;
  let latest = null;
  let drawnNews = null;
  const chart = new TimelineChart(document.getElementById('timeline'), '#timeline-note');
  bindMapButtons(() => map);
  const name = (i) => run.robots[i]?.name ?? String(i);
  const onLinkClick = (from, to) => {
    const link = latest?.links.find((l) => l[1] === from && l[2] === to);
    if (link) showLink(run, link);
  };
  const poll = async () => {
    let live;
    try {
      live = await loadLive();
    } catch (error) {
      select('#time-label').text('run ended: replay its folder with sitlnet view');
      document.body.dataset.ended = 'true';
      return;
    }
    latest = live;
    // Drawn only when something new came: the server rebuilds the document at most every
    // 200 ms, and a paused or slow run sends the same one again.
    const news = JSON.stringify([live.time_s, live.link_second, live.components_time_s,
      live.timing.length, live.modes, live.gcs]);
    if (live.time_s !== null && news !== drawnNews) {
      drawnNews = news;
      const here = live.robots.map((r) => [r[1], r[2]]);
      const trailPoints = live.trails.flatMap((t) => t.map((p) => [p[1], p[2]]));
      // Rescaled to keep the fleet in view, unless the user zoomed, panned or fitted it.
      if (!map || (!map.userMoved && !map.shows(here.concat(trailPoints)))) {
        const around = here.flatMap(([x, y]) => kMarginPoints.map(([dx, dy]) => [x + dx, y + dy]));
        map = new MapView(document.getElementById('map'), run,
          pointsToShow(run, here.concat(trailPoints, around)), onLinkClick);
      }
      const trails = live.trails.map((t) => t.map((p) => [p[0], p[1], p[2]]));
      const vehicles = vehiclesByRobot(live.gcs, run.robots.length);
      map.draw(run, live.robots, trails, live.links, vehicles.map(statusLine));
      const now = live.connectivity[live.connectivity.length - 1];
      const modes = run.robots.map(() => null);
      for (const [, robot, mode] of live.modes) modes[robot] = mode;
      drawRobotTable(run, live.robots, now?.[2], modes, vehicles);
      document.body.dataset.gcsTimeS = live.gcs_time_s ?? '';
      const lastSecond = live.timing[live.timing.length - 1]?.[0] ?? -1;
      chart.draw(live.connectivity, live.timing, Math.max(live.time_s, 1),
        live.components_time_s ?? 0, lastSecond, name);
      document.body.dataset.componentsTimeS = live.components_time_s ?? '';
      select('#time-label').text(`${live.time_s.toFixed(1)} s (live)`);
      select('#time').property('value', live.time_s).property('max', run.end_s);
      document.body.dataset.liveTimeS = live.time_s;
      document.body.dataset.linkSecond = live.link_second;
      document.body.dataset.ready = 'true';
    }
    setTimeout(poll, kPollMs);
  };
  await poll();
}
