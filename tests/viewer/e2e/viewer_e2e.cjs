// The viewer's page end to end in headless Chromium (playwright-core): the page loads, the first
// frame appears, a drag changes the view, a catalogue switch changes the frame, a nudge moves the
// glasses and saving writes a placement (a second save over an existing file asks first and keeps a
// backup), a malformed message gets an error and the server keeps serving, a snapshot arrives; on a
// touch screen (a second client with touch input, real touch events through the DevTools protocol)
// one finger orbits, two fingers pinch to zoom and move together to pan.
// Usage: node viewer_e2e.cjs URL WORK CHROMIUM (WORK holds node_modules, catalogue/, screens/).
"use strict";
const fs = require("fs");
const path = require("path");
const [, , url, work, chromiumPath] = process.argv;
const { chromium } = require(path.join(work, "node_modules", "playwright-core"));

const screens = path.join(work, "screens");
let failures = 0;
const ok = (name) => console.log(`ok - ${name}`);
const check = (cond, name) => {
  if (cond) ok(name);
  else { failures++; console.log(`not ok - ${name}`); }
};

// A second client on a touch screen: the gestures go in as touch events (Input.dispatchTouchEvent),
// which Chromium turns into the pointer events the page listens to.
async function touchGestures(browser, url, check) {
  const context = await browser.newContext({ viewport: { width: 1280, height: 860 }, hasTouch: true });
  const page = await context.newPage();
  const wait = (fn, arg, timeout = 60000) => page.waitForFunction(fn, arg, { timeout, polling: 50 });
  const canvas = () => page.evaluate(() => document.getElementById("view").toDataURL("image/png"));
  try {
    await page.goto(url);
    await wait(() => window.lgnViewer && window.lgnViewer.fullFrames >= 1);
    const cdp = await context.newCDPSession(page);
    const box = await page.locator("#view").boundingBox();
    const cx = box.x + box.width / 2, cy = box.y + box.height / 2;
    // fingers(t): the touch points at step t of 0..steps.
    const gesture = async (fingers, steps = 8) => {
      const at = (t) => fingers(t).map(([x, y], id) => ({ x, y, id }));
      await cdp.send("Input.dispatchTouchEvent", { type: "touchStart", touchPoints: at(0) });
      for (let t = 1; t <= steps; t++) {
        await cdp.send("Input.dispatchTouchEvent", { type: "touchMove", touchPoints: at(t / steps) });
        await page.waitForTimeout(20);
      }
      await cdp.send("Input.dispatchTouchEvent", { type: "touchEnd", touchPoints: [] });
      await page.waitForTimeout(100);
      await wait(() => { const v = window.lgnViewer, f = v.lastFrame; return f && f.kind === "full" && f.seq === v.lastSentSeq; });
    };
    const orbit = () => page.evaluate(() => ({ ...window.lgnViewer.orbit }));
    const before = await canvas(), o0 = await orbit();
    await gesture((t) => [[cx + 120 * t, cy + 10 * t]]);
    const o1 = await orbit();
    check(o1.yaw < o0.yaw && (await canvas()) !== before, "touch: one finger orbits the head");
    await gesture((t) => [[cx - 40 - 60 * t, cy], [cx + 40 + 60 * t, cy]]);
    const o2 = await orbit();
    check(o2.distance < o1.distance, "touch: two fingers spreading zoom in");
    await gesture((t) => [[cx - 50 + 80 * t, cy + 30 * t], [cx + 50 + 80 * t, cy + 30 * t]]);
    const o3 = await orbit();
    console.log(`# touch orbits: ${JSON.stringify([o0, o1, o2, o3])}`);
    check(o3.pan_x !== o2.pan_x && o3.pan_y !== o2.pan_y && Math.abs(o3.distance / o2.distance - 1) < 1e-6,
          "touch: two fingers moving together pan");
    await page.screenshot({ path: path.join(screens, "07-touch.png") });
  } finally {
    await context.close();
  }
}

(async () => {
  const browser = await chromium.launch({ executablePath: chromiumPath, headless: true, args: ["--no-sandbox"] });
  const page = await browser.newPage({ viewport: { width: 1280, height: 860 } });
  const dialogs = [];
  page.on("dialog", (d) => { dialogs.push(d.message()); d.accept(); });
  page.on("pageerror", (e) => { failures++; console.log(`not ok - page error: ${e.message}`); });
  const wait = (fn, arg, timeout = 60000) => page.waitForFunction(fn, arg, { timeout, polling: 50 });
  const canvas = () => page.evaluate(() => document.getElementById("view").toDataURL("image/png"));
  const shot = (name) => page.screenshot({ path: path.join(screens, name) });
  // Waits for a full frame that arrived after the newest state message and after `since`.
  const fullAfterState = async () => {
    const since = await page.evaluate(() => performance.now());
    await wait((t) => window.lgnViewer.lastFullAt > Math.max(t, window.lgnViewer.stateAt), since);
  };
  // Waits for the full frame of the newest camera (the last one goes out on the next animation frame).
  const fullForLatestCamera = async () => {
    await page.waitForTimeout(100);
    await wait(() => { const v = window.lgnViewer, f = v.lastFrame; return f && f.kind === "full" && f.seq === v.lastSentSeq; });
  };
  try {
    await page.goto(url);
    check((await page.title()).includes("Lorgnette"), "page loads");

    await wait(() => window.lgnViewer && window.lgnViewer.fullFrames >= 1);
    check(true, "first frame appears");
    await shot("01-first-frame.png");
    const first = await canvas();

    const box = await page.locator("#view").boundingBox();
    const cx = box.x + box.width / 2, cy = box.y + box.height / 2;
    await page.mouse.move(cx, cy);
    await page.mouse.down();
    for (let i = 1; i <= 10; i++) await page.mouse.move(cx + 15 * i, cy + 3 * i);
    await page.mouse.up();
    await fullForLatestCamera();
    const dragged = await canvas();
    check(dragged !== first, "a drag changes the view");
    await shot("02-dragged.png");

    await page.click('.thumb[data-index="1"]');
    await wait(() => window.lgnViewer.state && window.lgnViewer.state.frame.index === 1);
    await fullAfterState();
    const switched = await canvas();
    check(switched !== dragged, "a catalogue switch changes the frame");
    await shot("03-catalogue-switch.png");

    for (let i = 0; i < 4; i++) await page.click('button[data-nudge="up_mm"][data-amount="0.5"]');
    await wait(() => window.lgnViewer.state.nudge.up_mm >= 2);
    await fullAfterState();
    const nudged = await canvas();
    check(nudged !== switched, "a nudge moves the glasses");
    await shot("04-nudged.png");
    await page.click("#save");
    await wait(() => window.lgnViewer.saved.length >= 1);
    const saved = path.join(work, "catalogue", "b-rect.glb.placement.json");
    const written = fs.existsSync(saved) && JSON.parse(fs.readFileSync(saved, "utf8"));
    check(written && written.nudge && written.nudge.up_mm === 2, "saving writes a placement with the nudge");

    // Frame 0 has a placement file already: saving over it asks first and keeps a backup.
    await page.click('.thumb[data-index="0"]');
    await wait(() => window.lgnViewer.state.frame.index === 0);
    await page.click('button[data-nudge="forward_mm"][data-amount="0.5"]');
    await wait(() => window.lgnViewer.state.nudge.forward_mm > 0);
    await page.click("#save");
    await wait(() => window.lgnViewer.saved.length >= 2);
    const backups = fs.readdirSync(path.join(work, "catalogue")).filter((f) => f.startsWith("a-round.glb.placement.json.") && f.endsWith(".bak"));
    check(dialogs.length === 1 && backups.length === 1, "replacing a placement asks first and keeps a backup");

    const errorsBefore = await page.evaluate(() => window.lgnViewer.errors.length);
    await page.evaluate(() => window.lgnViewer.sendRaw("{this is not json"));
    await wait((n) => window.lgnViewer.errors.length > n, errorsBefore);
    const err = await page.evaluate(() => window.lgnViewer.errors[window.lgnViewer.errors.length - 1]);
    await page.click("#reset-view");
    await page.mouse.move(cx, cy);
    await page.mouse.down();
    await page.mouse.move(cx - 60, cy);
    await page.mouse.up();
    await fullForLatestCamera();
    check(err.code === "malformed" && (await page.evaluate(() => window.lgnViewer.connected)),
          "a malformed message gets an error and the server keeps serving");

    await page.click("#toggle");
    await fullAfterState();
    await shot("05-glasses-off.png");
    await page.click("#toggle");
    await fullAfterState();
    await page.click("#snapshot");
    await wait(() => window.lgnViewer.snapshots >= 1);
    check(true, "a snapshot arrives as PNG");
    await shot("06-final.png");

    await touchGestures(browser, url, check);
  } catch (e) {
    failures++;
    console.log(`not ok - ${e.message}`);
    await shot("failure.png").catch(() => {});
  } finally {
    await browser.close();
  }
  console.log(failures ? `${failures} failure(s)` : "all passed");
  process.exit(failures ? 1 : 0);
})();
