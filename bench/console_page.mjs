// The console page's figures (issue 19), measured in headless chromium (playwright-core from
// tests/browser) against a live base:
//   - update latency: a keyframe received at the base -> the page showing the snapshot with it
//     (the page's own record, app.js noteUpdateLag; base and page share the machine's clock);
//   - bytes per second the open page receives (every response and the event stream, from the
//     DevTools protocol), in steady state (after the first 20 s);
//   - the page's JavaScript heap over the mission, and at its end.
// Two runs:
//   node bench/console_page.mjs mission [world] [speed]      # cairn_mission (default office, 1x)
//   node bench/console_page.mjs replay  [log] [log speed]    # cairn_base + one cairn_agent --log
//                                                            # (default Intel, 45 min of log, 8x)
// Needs a build (build/bin) and scripts/install_deps.sh (chromium, npm packages).
import { spawn } from "node:child_process";
import { mkdtempSync } from "node:fs";
import { createServer } from "node:net";
import { tmpdir } from "node:os";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const root = join(dirname(fileURLToPath(import.meta.url)), "..");
const { chromium } = await import(join(root, "tests/browser/node_modules/playwright-core/index.mjs"));
const [mode = "mission", what, speedArg] = process.argv.slice(2);
const bin = (name) => join(root, "build/bin", name);
const out = mkdtempSync(join(tmpdir(), "cairn-page-"));
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const freePort = () => new Promise((resolve) => {
  const s = createServer().listen(0, "127.0.0.1", () => { const { port } = s.address(); s.close(() => resolve(port)); });
});

const port = await freePort();
const children = [];
const start = (cmd, args) => {
  const child = spawn(cmd, args, { stdio: ["ignore", "ignore", "ignore"] });
  children.push(child);
  return new Promise((resolve) => child.on("exit", (code) => resolve(code)));
};
let done;
if (mode === "mission") {
  const world = what || join(root, "worlds/office.yaml");
  done = start(bin("cairn_mission"), ["--world", world, "--out", out, "--port", String(port), "--speed", speedArg || "1"]);
} else if (mode === "replay") {
  const log = what || join(root, "../shared/data/carmen/intel/intel.gfs.log");
  const domain = String(100 + (process.pid % 100));
  done = start(bin("cairn_base"), ["--out", join(out, "map"), "--robots", "1", "--port", String(port), "--domain", domain]);
  await sleep(1500);
  start(bin("cairn_agent"), ["--robot", "0", "--domain", domain, "--log", log, "--log-speed", speedArg || "8"]);
} else {
  console.error(`unknown mode ${mode}: mission or replay`);
  process.exit(2);
}

const base = `http://127.0.0.1:${port}`;
for (let i = 0; i < 120; ++i) {
  if (await fetch(`${base}/api/status`).then((r) => r.ok, () => false)) break;
  await sleep(500);
}
const browser = await chromium.launch({ executablePath: process.env.CAIRN_CHROMIUM || "/usr/bin/chromium", args: ["--no-sandbox"] });
const page = await browser.newPage({ viewport: { width: 1400, height: 1000 } });
const cdp = await page.context().newCDPSession(page);
await cdp.send("Network.enable");
await cdp.send("Performance.enable");
let bytes = 0;
const kindOf = new Map();  // request id -> "tiles", "events", "api", "other"
const urlOf = new Map();
const bytesByPath = {};
const bytesByKind = {};
const count = (id, n) => {
  bytes += n;
  const kind = kindOf.get(id) || "other";
  const path = (urlOf.get(id) || "?").replace(/^https?:\/\/[^/]+/, "").replace(/\?.*$/, "").replace(/\/-?\d+\/-?\d+\/-?\d+\.png$/, "/z/x/y.png");
  bytesByPath[path] = (bytesByPath[path] || 0) + n;
  bytesByKind[kind] = (bytesByKind[kind] || 0) + n;
};
// Every byte on the wire: each response's headers and body as they arrive (a 304 is headers only).
cdp.on("Network.requestWillBeSent", (e) => {
  const u = e.request.url;
  urlOf.set(e.requestId, u);
  kindOf.set(e.requestId, u.includes("/api/tiles/") ? "tiles" : u.includes("/api/events") ? "events" : u.includes("/api/") ? "api" : "other");
});
cdp.on("Network.dataReceived", (e) => count(e.requestId, e.encodedDataLength));
cdp.on("Network.responseReceived", (e) => count(e.requestId, e.response.encodedDataLength || 0));
const t0 = Date.now();
await page.goto(base + "/");
let steady = null;  // {t, bytes} at 20 s
const samples = [];
let finished = false;
done.then(() => { finished = true; });
let missionTime = 0;
while (!finished) {
  await sleep(5000);
  const t_s = (Date.now() - t0) / 1000;
  if (!steady && t_s >= 20) steady = { t_s, bytes };
  const metrics = await cdp.send("Performance.getMetrics").catch(() => null);
  if (!metrics) break;
  const heap = metrics.metrics.find((m) => m.name === "JSHeapUsedSize").value;
  missionTime = await page.evaluate(() => document.getElementById("mission-time").textContent).catch(() => "?");
  samples.push({ t_s, heap_mb: heap / 1e6, bytes });
  console.log(`${t_s.toFixed(0)} s: mission ${missionTime}, page heap ${(heap / 1e6).toFixed(1)} MB, ${(bytes / 1e3).toFixed(0)} kB received`);
}
const lags = await page.evaluate(() => window.cairnUpdateLags.slice()).catch(() => []);
// The heap the page keeps after the mission: garbage collected first (the samples above include
// garbage not yet collected).
await cdp.send("HeapProfiler.enable").catch(() => {});
await cdp.send("HeapProfiler.collectGarbage").catch(() => {});
const kept = await cdp.send("Performance.getMetrics").then((m) => m.metrics.find((x) => x.name === "JSHeapUsedSize").value / 1e6, () => NaN);
await browser.close();
for (const c of children) if (c.exitCode === null) c.kill("SIGTERM");

const pct = (v, p) => { const s = [...v].sort((a, b) => a - b); return s.length ? s[Math.min(s.length - 1, Math.floor(p * s.length))] : NaN; };
const last = samples[samples.length - 1] || { t_s: 0, bytes: 0, heap_mb: NaN };
const rate = steady && last.t_s > steady.t_s ? (last.bytes - steady.bytes) / (last.t_s - steady.t_s) : NaN;
console.log(`\nmode ${mode}: ${samples.length} samples over ${last.t_s.toFixed(0)} s of wall time, mission time ${missionTime}`);
console.log(`update latency (keyframe at the base -> page shows it): p50 ${(1000 * pct(lags, 0.5)).toFixed(0)} ms, ` +
  `p95 ${(1000 * pct(lags, 0.95)).toFixed(0)} ms over ${lags.length} updates`);
console.log(`bytes to the page in steady state: ${(rate / 1e3).toFixed(1)} kB/s (${(last.bytes / 1e6).toFixed(2)} MB in all)`);
console.log(`bytes by kind: ${Object.entries(bytesByKind).map(([k, v]) => `${k} ${(v / 1e6).toFixed(2)} MB`).join(", ")}`);
if (process.env.CAIRN_BENCH_DETAIL) console.log(Object.entries(bytesByPath).sort((a, b) => b[1] - a[1]).slice(0, 10));
console.log(`page heap: ${kept.toFixed(1)} MB kept after the mission (garbage collected); ` +
  `${last.heap_mb.toFixed(1)} MB at the last sample, max ${Math.max(...samples.map((s) => s.heap_mb)).toFixed(1)} MB`);
