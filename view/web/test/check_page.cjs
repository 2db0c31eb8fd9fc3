// Drives the page of `sitlnet view` in Debian's Chromium (playwright-core, no browser of its
// own) for tests/integration/view_browser_test.cc, which holds the oracles (trajectories.csv,
// losses.csv.gz). Usage: node check_page.cjs [--link FROM,TO] URL ARTIFACT_DIR TIME_S...
// It clicks the link FROM -> TO (default: the first drawn) at the last time.
// With --live (sitlnet run --view): node check_page.cjs --live URL ARTIFACT_DIR READS reads the
// page READS times, each after the page has drawn a newer time.
// Prints one fact a line:
//   load_ms MS                      navigation to the page's first drawing
//   console_error TEXT              every console error, page error and failed request
//   scale PX_PER_M MIN_X_M MAX_Y_M  the map's projection (data attributes of the svg)
//   robot TIME_S INDEX CX_PX CY_PX  a robot's drawn centre, CSS px from the svg's top-left corner
//   mode TIME_S INDEX MODE          (replay) a robot's autopilot mode in the robot table
//   frames FROM TO START_NS END_NS TOTAL   the clicked link's frame list, then each row:
//   frame CELL,CELL,...
//   timeline TIME_S MAX_COMPONENTS CURSOR_TIME_S COMPONENTS_TIME_S COMPONENTS COMPONENT_OF
//            TIMING_SECOND ITERATIONS STF_MEAN STF_MAX LAG_MAX_MS   the timeline at each time
//            (live: at each read; COMPONENT_OF is comma-separated; a field left empty is "-")
//   screenshot PATH
//   live TIME_S LINK_SECOND         (--live) the time and links.csv second drawn, then the
//   scale ...                       map's scale then (it rescales when robots leave it),
//   robot TIME_S INDEX CX_PX CY_PX  the robots and each drawn link:
//   link FROM TO FRAMES DELIVERED
const fs = require('node:fs');
const { openBrowser, printErrors, runDriver, screenshot } = require('./browser.cjs');

// The timeline's facts at the time shown (data attributes of svg#timeline).
async function timelineFacts(page) {
  return page.$eval('#timeline', (svg) => {
    const d = svg.dataset;
    return [d.maxComponents, d.cursorTimeS, d.componentsTimeS, d.components, d.componentOf, d.timingSecond,
      d.iterations, d.stfMean, d.stfMax, d.lagMaxMs].map((v) => (v === undefined || v === '' ? '-' : v));
  });
}

async function robotCentres(page) {
  return page.$$eval('#map circle.robot', (circles) => {
    const svg = document.getElementById('map').getBoundingClientRect();
    return circles.map((c) => {
      const box = c.getBoundingClientRect();
      return [c.dataset.robot, box.x + box.width / 2 - svg.x, box.y + box.height / 2 - svg.y];
    });
  });
}

// The live page's time, robots and links, read in one go (the page draws between tasks).
async function readLive(page) {
  return page.evaluate(() => {
    const svg = document.getElementById('map').getBoundingClientRect();
    const robots = [...document.querySelectorAll('#map circle.robot')].map((c) => {
      const box = c.getBoundingClientRect();
      return [c.dataset.timeS, c.dataset.robot, box.x + box.width / 2 - svg.x,
        box.y + box.height / 2 - svg.y];
    });
    const links = [...document.querySelectorAll('#map line.link')].map((l) =>
      [l.dataset.from, l.dataset.to, l.dataset.frames, l.dataset.delivered]);
    const map = document.getElementById('map').dataset;
    return { time: document.body.dataset.liveTimeS, second: document.body.dataset.linkSecond,
      scale: [map.pxPerM, map.minXM, map.maxYM], robots, links };
  });
}

async function checkLive(page, reads, shot) {
  let last = null;
  for (let i = 0; i < reads; ++i) {
    // A newer time, with a whole second of links.
    await page.waitForFunction((t) => document.body.dataset.liveTimeS !== undefined &&
      document.body.dataset.liveTimeS !== t && Number(document.body.dataset.linkSecond) >= 0,
    last, { timeout: 30000 });
    const live = await readLive(page);
    last = live.time;
    console.log(`live ${live.time} ${live.second}`);
    console.log(`scale ${live.scale.join(' ')}`);
    for (const [time, index, x, y] of live.robots) console.log(`robot ${time} ${index} ${x} ${y}`);
    for (const link of live.links) console.log(`link ${link.join(' ')}`);
    // Its own times say what it shows: read apart from the map, it may be of the next poll.
    console.log(`timeline ${live.time} ${(await timelineFacts(page)).join(' ')}`);
    await shot(`live-${i}.png`);
  }
}

async function main() {
  const args = process.argv.slice(2);
  const liveAt = args.indexOf('--live');
  if (liveAt >= 0) args.splice(liveAt, 1);
  const linkAt = args.indexOf('--link');
  const [linkFrom, linkTo] = linkAt >= 0 ? args.splice(linkAt, 2)[1].split(',') : [];
  const [url, artifacts, ...times] = args;
  fs.mkdirSync(artifacts, { recursive: true });
  const { page, close } = await openBrowser();
  try {
    printErrors(page);
    const start = Date.now();
    await page.goto(url);
    await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
    console.log(`load_ms ${Date.now() - start}`);
    const scale = await page.$eval('#map', (svg) =>
      [svg.dataset.pxPerM, svg.dataset.minXM, svg.dataset.maxYM]);
    console.log(`scale ${scale.join(' ')}`);
    const shot = (name) => screenshot(page, artifacts, name);
    if (liveAt >= 0) {
      await checkLive(page, Number(times[0]), shot);
      return;
    }
    for (const time of times) {
      await page.$eval('#time', (slider, t) => {
        slider.value = t;
        slider.dispatchEvent(new Event('input'));
      }, time);
      for (const [index, x, y] of await robotCentres(page)) console.log(`robot ${time} ${index} ${x} ${y}`);
      const modes = await page.$$eval('#robots tbody tr', (rows) =>
        rows.map((tr) => [tr.dataset.robot, tr.dataset.mode]));
      for (const [index, mode] of modes) console.log(`mode ${time} ${index} ${mode}`);
      console.log(`timeline ${time} ${(await timelineFacts(page)).join(' ')}`);
      await shot(`replay-${time}s.png`);
    }
    // The link asked for, or the first drawn, at the last time; the table says which link the
    // click selected (links drawn side by side may overlap).
    const link = linkFrom === undefined
      ? page.locator('#map line.link').first()
      : page.locator(`#map line.link[data-from="${linkFrom}"][data-to="${linkTo}"]`);
    await link.click();
    await page.waitForSelector('#frames[data-from]', { timeout: 10000 });
    const frames = await page.$eval('#frames', (table) => ({
      head: [table.dataset.from, table.dataset.to, table.dataset.startNs, table.dataset.endNs,
        table.dataset.total],
      rows: [...table.querySelectorAll('tbody tr')].map((tr) =>
        [...tr.querySelectorAll('td')].map((td) => td.textContent).join(',')),
    }));
    console.log(`frames ${frames.head.join(' ')}`);
    for (const row of frames.rows) console.log(`frame ${row}`);
    await shot('replay-link.png');
  } finally {
    await close();
  }
}

runDriver(main);
