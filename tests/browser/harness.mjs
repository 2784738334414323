// What the browser tests share: skipping loudly, checks, waiting, a free port, a live mission
// (cairn_mission with the console on that port) and chromium through playwright-core.
// A test: const t = await startMission(...); try { ...t.check(...)... } catch (e) { t.check(false, e.message) }
// finally { await t.finish("screenshot.png") }, which exits 0 (passed) or 1 (failed, with the
// mission's output).
import { spawn } from "node:child_process";
import { existsSync, mkdirSync } from "node:fs";
import { createServer } from "node:net";
import { join } from "node:path";

export const CHROMIUM = process.env.CAIRN_CHROMIUM || "/usr/bin/chromium";
export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

/// Exit 77 (ctest's skip) with the reason: never a silent pass.
export function skip(why) {
  console.log(`SKIPPED: ${why}`);
  process.exit(77);
}

export async function loadPlaywright() {
  try {
    const playwright = await import("playwright-core");
    if (!existsSync(CHROMIUM)) skip(`no chromium at ${CHROMIUM} (apt-get install chromium)`);
    return playwright;
  } catch {
    skip("playwright-core is not installed (scripts/install_deps.sh runs npm ci in tests/browser)");
  }
}

export async function waitFor(what, timeoutMs, probe) {
  const until = Date.now() + timeoutMs;
  while (Date.now() < until) {
    const v = await probe().catch(() => null);
    if (v) return v;
    await sleep(250);
  }
  throw new Error(`timed out after ${timeoutMs / 1000} s waiting for ${what}`);
}

function freePort() {
  return new Promise((resolve) => {
    const s = createServer().listen(0, "127.0.0.1", () => {
      const { port } = s.address();
      s.close(() => resolve(port));
    });
  });
}

/// Starts cairn_mission on `world` (extra arguments after it) with the console on a free port, and
/// chromium. Returns {base, getJson, browser, missionExit, check, finish}.
export async function startMission(binDir, world, outDir, extraArgs) {
  const playwright = await loadPlaywright();
  mkdirSync(outDir, { recursive: true });
  const port = await freePort();
  const base = `http://127.0.0.1:${port}`;
  const mission = spawn(join(binDir, "cairn_mission"),
    ["--world", world, "--out", join(outDir, "mission"), "--port", String(port), ...extraArgs],
    { stdio: ["ignore", "pipe", "pipe"] });
  let missionOutput = "";
  mission.stdout.on("data", (d) => { missionOutput += d; });
  mission.stderr.on("data", (d) => { missionOutput += d; });
  const missionExit = new Promise((resolve) => mission.on("exit", (code) => resolve(code)));
  const failures = [];
  const check = (ok, what) => {
    console.log(`${ok ? "ok  " : "FAIL"} ${what}`);
    if (!ok) failures.push(what);
  };
  const browser = await playwright.chromium.launch({ executablePath: CHROMIUM, args: ["--no-sandbox"] });
  const getJson = async (path) => (await fetch(base + path)).json();
  async function finish(screenshot) {
    await browser.close();
    if (mission.exitCode === null) mission.kill("SIGTERM");
    if (failures.length) {
      console.log(`--- mission output ---\n${missionOutput}`);
      console.log(`${failures.length} check(s) failed`);
      process.exit(1);
    }
    console.log(`all checks passed; screenshot ${screenshot}`);
  }
  return { base, getJson, browser, missionExit, check, finish };
}
