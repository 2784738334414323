// The console as an operator uses it, in a real browser (playwright-core driving Debian's chromium)
// against a live mission (cairn_mission, one robot, real time):
//   - watching without the operator token: the map and the robot are shown, commands are refused
//     in the page and nothing is sent;
//   - with the token: click the robot's marker, then a point on the map; the simulated robot drives
//     there (the path it plans drawn while it drives) and the command shows as done; an alert is
//     acknowledged and a victim confirmed by a click, and both are in summary.json; "All home" ends
//     the mission;
//   - at 400 px wide the page has no horizontal scroll;
//   - the printable mission report shows the map and the commands.
// Exit 0 passed, 1 failed, 77 skipped (no chromium or no node_modules: said loudly).
//   node tests/browser/console_commands.mjs <bin dir> <source dir> <out dir>
import { readFileSync } from "node:fs";
import { join } from "node:path";
import { sleep, startMission, waitFor } from "./harness.mjs";

const [binDir, sourceDir, outDir] = process.argv.slice(2);
const TOKEN = "b0a7c0de0123456789abcdef01234567";
const TARGET = { x: 6.0, y: 7.5 }; // down the office corridor from where robot 0 entered (1.2, 7.5)

const { base, getJson, browser, missionExit, check, finish } = await startMission(binDir,
  join(sourceDir, "tests/worlds/operator_one_robot.yaml"), outDir,
  ["--operator-token", TOKEN, "--speed", "1", "--timeout", "240"]);
try {
  await waitFor("robot 0 placed on the map", 90000, async () => {
    const robots = await getJson("/api/robots");
    return robots.some((r) => r.id === 0 && r.pose_m);
  });

  // Watching only: no token.
  const viewer = await browser.newPage({ viewport: { width: 1400, height: 1100 } });
  await viewer.goto(base + "/");
  await viewer.waitForSelector(".robot-marker", { timeout: 15000 });
  await viewer.waitForFunction(() => [...document.querySelectorAll(".occupancy-tiles img")].some((i) => i.naturalWidth === 256),
    null, { timeout: 15000 });
  check(true, "the map view shows the merged map as tiles");
  check((await viewer.textContent(".leaflet-control-scale")).trim().endsWith("m"), "the map view has a scale bar in metres");
  check((await viewer.textContent(".leaflet-control-layers")).includes("Trajectories"), "the map's layers can be switched");
  check(await viewer.waitForFunction(() => window.Cloud3D && typeof Cloud3D.show === "function", null, { timeout: 10000 })
    .then(() => true, () => false), "the 3D cloud view (three.js, served by the base) is loaded");
  check((await viewer.textContent("#operator-mode")) === "watching only", "without the token the page says it only watches");
  check(await viewer.isDisabled("button[data-all='stop']"), "without the token the command buttons are off");
  await viewer.click(".robot-marker");
  const p0 = await viewer.evaluate(([x, y]) => MapView.pixelOf(x, y), [TARGET.x, TARGET.y]);
  await viewer.click("#map", { position: p0 });
  await viewer.waitForFunction(() => document.getElementById("command-feedback").textContent.includes("Watching only"));
  check((await getJson("/api/commands")).length === 0, "a click without the token sends nothing");
  await viewer.close();

  // The operator: click the robot, then the point.
  const page = await browser.newPage({ viewport: { width: 1400, height: 1100 } });
  await page.goto(`${base}/#token=${TOKEN}`);
  await page.waitForSelector(".robot-marker", { timeout: 15000 });
  check((await page.textContent("#operator-mode")) === "operator", "the operator link turns commands on");
  check(!page.url().includes(TOKEN), "the token is taken out of the address bar");
  await page.click(".robot-marker");
  check((await page.textContent("#selected-robot")).startsWith("Robot 0 selected"), "clicking the marker selects robot 0");
  const feedback = () => page.textContent("#command-feedback");
  const sentGoto = () => page.waitForFunction(
    () => document.getElementById("command-feedback").textContent.startsWith("Sent goto"), null, { timeout: 15000 })
    .then(() => true, () => false);
  await page.click("#map", { position: await page.evaluate(([x, y]) => MapView.pixelOf(x, y), [TARGET.x, TARGET.y]) });
  if (!(await sentGoto())) {
    // Seen once on a loaded machine (the page's answer is printed to tell why); a second goto
    // overtakes the first, if it went, so the rest of the test is unchanged.
    console.log(`note: no goto sent after the first click (page says "${await feedback()}"); selecting and clicking again`);
    await page.click(".robot-marker");
    await page.click("#map", { position: await page.evaluate(([x, y]) => MapView.pixelOf(x, y), [TARGET.x, TARGET.y]) });
    check(await sentGoto(), `a click on the map sends the selected robot there (page says "${await feedback()}")`);
  }
  // The page says "Sent" when the POST returns; the commands list is the base's published state,
  // which can lag it by one update.
  const sent = await waitFor("the goto in the base's command list", 5000, async () => (await getJson("/api/commands"))[0]);
  check(sent && sent.kind === "goto" && Math.hypot(sent.x_m - TARGET.x, sent.y_m - TARGET.y) < 0.3,
    `the click named the point (${sent && sent.x_m.toFixed(2)}, ${sent && sent.y_m.toFixed(2)}) m`);
  // While it drives, the path its own planner chose is drawn from where it is (from its status).
  const drawn = await page.waitForSelector("path.planned-path", { timeout: 15000 }).then(() => true, () => false);
  const reported = (await getJson("/api/robots")).find((x) => x.id === 0);
  check(drawn, `the path robot 0 drives is drawn on the map (${reported && reported.path_m ? reported.path_m.length : 0} points reported now)`);
  await waitFor("the command shown as done", 60000, async () =>
    (await page.textContent("#commands")).includes("done"));
  const robot = await waitFor("robot 0 at the point", 10000, async () => {
    const r = (await getJson("/api/robots")).find((x) => x.id === 0);
    return r && r.pose_m && Math.hypot(r.pose_m[0] - TARGET.x, r.pose_m[1] - TARGET.y) < 0.8 ? r : null;
  });
  check(true, `robot 0 drove there: (${robot.pose_m[0].toFixed(2)}, ${robot.pose_m[1].toFixed(2)}) m`);

  // A keep-out area drawn with two clicks; a goto into it is refused, and the page says why.
  await page.click("#draw-keep-out");
  for (const [x, y] of [[8.0, 6.5], [10.0, 8.5]]) {
    await page.click("#map", { position: await page.evaluate(([a, b]) => MapView.pixelOf(a, b), [x, y]) });
  }
  const area = await waitFor("the keep-out area at the base", 10000, async () => (await getJson("/api/search")).keep_out[0]);
  check(Math.abs(area.min_m[0] - 8) < 0.3 && Math.abs(area.max_m[1] - 8.5) < 0.3,
    `the keep-out area is where it was drawn ([${area.min_m}] to [${area.max_m}])`);
  await page.waitForSelector("path.keep-out", { timeout: 10000 });
  check((await page.textContent("#selected-robot")).startsWith("Robot 0 selected"), "robot 0 is still selected");
  await page.click("#map", { position: await page.evaluate(([a, b]) => MapView.pixelOf(a, b), [9.0, 7.5]) });
  const refused = await page.waitForFunction(() => document.getElementById("command-feedback").textContent.includes("keep-out area 1"),
    null, { timeout: 10000 }).then(() => true, () => false);
  check(refused, `a goto into the keep-out area is refused with the reason ("${await page.textContent("#command-feedback")}")`);

  // Sent where the victim is in view; its alert acknowledged and the victim confirmed, each by a
  // click: both reach the base.
  await page.click("#map", { position: await page.evaluate(([a, b]) => MapView.pixelOf(a, b), [2.5, 2.8]) });
  const victim = await waitFor("robot 0 to find the victim", 120000,
    async () => (await getJson("/api/objects")).find((o) => o.class === "victim"));
  check(true, `robot 0 found victim ${victim.id}`);
  const victimAlert = page.locator("#alerts li", { hasText: /victim/i }).locator("button.ack").first();
  await victimAlert.click({ timeout: 30000 });
  const acked = await waitFor("the acknowledgement at the base", 10000,
    async () => (await getJson("/api/alerts/log")).find((a) => a.acked));
  check(/victim/i.test(acked.text), `the alert "${acked.text}" was acknowledged by a click`);
  await page.locator("#objects button.judge.confirmed").first().click({ timeout: 30000 });
  const judged = await waitFor("the verdict at the base", 10000,
    async () => (await getJson("/api/objects")).find((o) => o.verdict === "confirmed"));
  check(judged.id === victim.id, `victim ${judged.id} was confirmed by a click`);
  // Pause and resume the exploration.
  await page.click("#pause-search");
  await waitFor("exploration paused", 10000, async () => (await getJson("/api/search")).paused);
  await page.waitForFunction(() => !document.getElementById("search-state").hidden);
  check((await page.textContent("#pause-search")) === "Resume exploration", "the page shows the exploration paused");
  await page.screenshot({ path: join(outDir, "console_operator.png"), fullPage: true });
  await page.click("#pause-search");
  await waitFor("exploration resumed", 10000, async () => !(await getJson("/api/search")).paused);
  check(true, "the exploration resumed from the page");

  // A phone: 400 px wide, no horizontal scroll.
  await page.setViewportSize({ width: 400, height: 900 });
  await sleep(300);
  const overflow = await page.evaluate(() => document.documentElement.scrollWidth - window.innerWidth);
  check(overflow <= 0, `no horizontal scroll at 400 px (${overflow} px too wide)`);
  await page.setViewportSize({ width: 1400, height: 1100 });

  // The printable mission report, from the same live API.
  const report = await browser.newPage({ viewport: { width: 1000, height: 1400 } });
  await report.goto(`${base}/report.html`);
  await report.waitForFunction(() => document.getElementById("r-robot-rows").textContent.includes("Robot 0"));
  check((await report.textContent("#r-commands")).includes("goto"), "the mission report lists the operator's commands");
  check(await report.evaluate(() => new Promise((ok) => {
    const img = document.getElementById("r-map");
    if (img.complete && img.naturalWidth > 0) ok(true);
    img.onload = () => ok(true);
    img.onerror = () => ok(false);
  })), "the mission report shows the map");
  await report.screenshot({ path: join(outDir, "mission_report.png"), fullPage: true });
  await report.close();

  await page.click("button[data-all='home']");
  const code = await Promise.race([missionExit, sleep(120000).then(() => "timeout")]);
  check(code === 0, `"All home" ends the mission (exit ${code})`);
  // What the operator did is in the mission's record (and its journal, read back after a restart).
  const summary = JSON.parse(readFileSync(join(outDir, "mission", "map", "summary.json"), "utf8"));
  check(summary.alerts_acknowledged.includes(acked.key), `summary.json lists the acknowledged alert ${acked.key}`);
  check(summary.verdicts.some((v) => v.verdict === "confirmed"), "summary.json lists the confirmed victim");
} catch (e) {
  check(false, e.message);
} finally {
  await finish(join(outDir, "console_operator.png"));
}
