// Drives the map of `sitlnet view` in Debian's Chromium for tests/integration/view_browser_test.cc
// (ViewBrowserTest.TheCaseStudySplit...), which holds the oracles: the robot table's GCS columns,
// labels that do not overlap, fit the fleet, the wheel's zoom and a drag's pan.
// Usage: node check_map.cjs URL ARTIFACT_DIR TIME_S
// Prints one fact a line (px are CSS px from the drawing's top-left corner, inside the border):
//   console_error TEXT                       every console error, page error and failed request
//   gcs INDEX SYSTEM_ID MODE ARMED LOSS      a robot table row's GCS columns ("-": none)
//   view STAGE WIDTH_PX HEIGHT_PX PX_PER_M MIN_X_M MAX_Y_M   the svg and its scale
//   robot STAGE INDEX CX_PX CY_PX            a robot's drawn centre
//   label STAGE INDEX X_PX Y_PX WIDTH_PX HEIGHT_PX   its label's box
//   link STAGE FROM TO X1 Y1 X2 Y2           a drawn link's ends
//   anchor X_PX Y_PX                         where the wheel turned (robot 0's centre)
//   selected FROM,TO or -                    the link the frame list shows after the drag
//   screenshot PATH
// STAGE: whole (as loaded, at TIME_S), fit (after "Fit the fleet"), zoom (then the wheel, 3
// notches in, over robot 0), pan (then a drag of +60, +40 px from the svg's middle).
const fs = require('node:fs');
const { gcsRows, openBrowser, printErrors, runDriver, screenshot } = require('./browser.cjs');

// The map's facts, read in one go.
async function readMap(page, stage) {
  const facts = await page.evaluate(() => {
    const svg = document.getElementById('map');
    const outer = svg.getBoundingClientRect();
    // The drawing's origin: inside the svg's border, where its px coordinates start.
    const origin = { x: outer.x + svg.clientLeft, y: outer.y + svg.clientTop };
    const rel = (box) => [box.x - origin.x, box.y - origin.y, box.width, box.height];
    const centre = (el) => {
      const [x, y, w, h] = rel(el.getBoundingClientRect());
      return [x + w / 2, y + h / 2];
    };
    return {
      view: [svg.clientWidth, svg.clientHeight, svg.dataset.pxPerM, svg.dataset.minXM, svg.dataset.maxYM],
      robots: [...svg.querySelectorAll('circle.robot')].map((c) => [c.dataset.robot, ...centre(c)]),
      labels: [...svg.querySelectorAll('text.robot-label')].map((t) =>
        [t.dataset.robot, ...rel(t.getBoundingClientRect())]),
      links: [...svg.querySelectorAll('line.link')].map((l) => [l.dataset.from, l.dataset.to,
        ...['x1', 'y1', 'x2', 'y2'].map((a) => l.getAttribute(a))]),
    };
  });
  console.log(`view ${stage} ${facts.view.join(' ')}`);
  for (const r of facts.robots) console.log(`robot ${stage} ${r.join(' ')}`);
  for (const l of facts.labels) console.log(`label ${stage} ${l.join(' ')}`);
  for (const l of facts.links) console.log(`link ${stage} ${l.join(' ')}`);
  return facts;
}

async function main() {
  const [url, artifacts, time] = process.argv.slice(2);
  fs.mkdirSync(artifacts, { recursive: true });
  const { page, close } = await openBrowser();
  const shot = (name) => screenshot(page, artifacts, name);
  try {
    printErrors(page);
    await page.goto(url);
    await page.waitForSelector('body[data-ready="true"]', { timeout: 30000 });
    await page.$eval('#time', (slider, t) => {
      slider.value = t;
      slider.dispatchEvent(new Event('input'));
    }, time);
    for (const row of await gcsRows(page)) console.log(`gcs ${row.join(' ')}`);
    await readMap(page, 'whole');
    await shot('map-whole.png');

    await page.click('#fit-fleet');
    const fit = await readMap(page, 'fit');
    await shot('map-fit.png');

    const svgBox = await page.$eval('#map', (svg) => {
      const b = svg.getBoundingClientRect();
      return { x: b.x + svg.clientLeft, y: b.y + svg.clientTop, width: svg.clientWidth, height: svg.clientHeight };
    });
    const [, ax, ay] = fit.robots.find((r) => r[0] === '0');
    console.log(`anchor ${ax} ${ay}`);
    await page.mouse.move(svgBox.x + ax, svgBox.y + ay);
    for (let notch = 0; notch < 3; ++notch) await page.mouse.wheel(0, -100);
    await page.waitForFunction((s) => document.getElementById('map').dataset.pxPerM !== s,
      fit.view[2], { timeout: 5000 });
    await readMap(page, 'zoom');
    await shot('map-zoom.png');

    const [mx, my] = [svgBox.x + svgBox.width / 2, svgBox.y + svgBox.height / 2];
    await page.mouse.move(mx, my);
    await page.mouse.down();
    await page.mouse.move(mx + 60, my + 40, { steps: 6 });
    await page.mouse.up();
    await readMap(page, 'pan');
    const selected = await page.$eval('#frames', (t) =>
      (t.dataset.from === undefined ? '-' : `${t.dataset.from},${t.dataset.to}`));
    console.log(`selected ${selected}`);
    await shot('map-pan.png');
  } finally {
    await close();
  }
}

runDriver(main);
