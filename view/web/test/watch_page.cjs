// Shows the live page of `sitlnet run --view` in Debian's Chromium (headless, as
// check_page.cjs starts it) until the run ends and the page says so, as someone watching would,
// then prints what the browser's processes cost. For bench/scale/view_ab.sh.
// Usage: node watch_page.cjs URL
// Prints: browser_cpu_s CPU_S wall_s WALL_S
//   CPU_S: user+system CPU seconds of every process under this one (Chromium's browser,
//   renderer, GPU and utility processes, and those already ended), from /proc/PID/stat.
// then:    page_s task T script S layout L style R layouts N styles M
//   the page's main thread as Chromium counts it (CDP Performance.getMetrics, seconds): all its
//   tasks, JavaScript, layout and style recalculation, and how many layouts and recalculations.
const fs = require('node:fs');
const { openBrowser } = require('./browser.cjs');

const kTicksPerS = 100;  // USER_HZ: /proc/PID/stat's clock ticks on Linux.

// CPU seconds of the processes under `root` (not `root` itself): their own and their reaped
// children's.
function descendantsCpuS(root) {
  const children = new Map();
  const ticks = new Map();
  for (const entry of fs.readdirSync('/proc')) {
    if (!/^\d+$/.test(entry)) continue;
    let stat;
    try {
      stat = fs.readFileSync(`/proc/${entry}/stat`, 'utf8');
    } catch {
      continue;  // Ended meanwhile.
    }
    // Fields after the command's closing parenthesis: state ppid ... utime(14) stime cutime cstime.
    const fields = stat.slice(stat.lastIndexOf(')') + 2).split(' ');
    const ppid = Number(fields[1]);
    if (!children.has(ppid)) children.set(ppid, []);
    children.get(ppid).push(Number(entry));
    ticks.set(Number(entry), fields.slice(11, 15).reduce((sum, f) => sum + Number(f), 0));
  }
  let total = 0;
  const stack = [...(children.get(root) ?? [])];
  while (stack.length > 0) {
    const pid = stack.pop();
    total += ticks.get(pid) ?? 0;
    stack.push(...(children.get(pid) ?? []));
  }
  return total / kTicksPerS;
}

async function main() {
  const [url] = process.argv.slice(2);
  const { context, page, close } = await openBrowser();
  const start = Date.now();
  try {
    const cdp = await context.newCDPSession(page);
    await cdp.send('Performance.enable');
    await page.goto(url);
    // Polled once a second: Playwright's default polls on every animation frame, which would
    // make Chromium draw 60 frames a second and be counted as the page's cost.
    await page.waitForFunction(() => document.body.dataset.ended === 'true', null,
      { polling: 1000, timeout: 3600 * 1000 });
    console.log(`browser_cpu_s ${descendantsCpuS(process.pid).toFixed(2)} ` +
      `wall_s ${((Date.now() - start) / 1000).toFixed(2)}`);
    const { metrics } = await cdp.send('Performance.getMetrics');
    const m = Object.fromEntries(metrics.map(({ name, value }) => [name, value]));
    console.log(`page_s task ${m.TaskDuration.toFixed(2)} script ${m.ScriptDuration.toFixed(2)} ` +
      `layout ${m.LayoutDuration.toFixed(2)} style ${m.RecalcStyleDuration.toFixed(2)} ` +
      `layouts ${m.LayoutCount} styles ${m.RecalcStyleCount}`);
  } finally {
    await close();
  }
}

main().catch((error) => {
  console.error(error.message);
  process.exit(1);
});
