// Reads the live view of `sitlnet run --view` as its page does, without a browser: the page's
// files, api/run, then api/live again kPollMs after each answer (view/web/src/live.js), each
// answer parsed, until the server stops answering at the run's end. It asks as Chromium does
// (its Accept-Encoding: the server's choice of compression is most of its cost). It measures
// what serving one watcher costs the run's host, without a browser's drawing. For
// bench/scale/view_ab.sh.
// Usage: node poll_live.cjs URL
// Prints: client_cpu_s CPU_S documents N bytes B wall_s WALL_S
//   CPU_S: this process's user+system CPU seconds (process.cpuUsage), its start included.
const kPollMs = 500;  // As view/web/src/live.js.
const kPageFiles = ['', 'style.css', 'app.js', 'favicon.svg', 'api/run'];
const kChromiumHeaders = { 'Accept-Encoding': 'gzip, deflate, br, zstd' };  // Chromium 156's.

async function get(url) {
  const response = await fetch(url, { headers: kChromiumHeaders });
  if (!response.ok) throw new Error(`${url}: ${response.status}`);
  return response.text();
}

async function main() {
  const [base] = process.argv.slice(2);
  const start = Date.now();
  let bytes = 0;
  for (const file of kPageFiles) bytes += (await get(base + file)).length;
  let documents = 0;
  for (;;) {
    let text;
    try {
      text = await get(`${base}api/live`);
    } catch {
      break;  // The run ended: its server stopped.
    }
    JSON.parse(text);
    bytes += text.length;
    documents += 1;
    await new Promise((resolve) => { setTimeout(resolve, kPollMs); });
  }
  const cpu = process.cpuUsage();
  console.log(`client_cpu_s ${((cpu.user + cpu.system) / 1e6).toFixed(3)} documents ${documents} ` +
    `bytes ${bytes} wall_s ${((Date.now() - start) / 1000).toFixed(2)}`);
}

main().catch((error) => {
  console.error(error.message);
  process.exit(1);
});
