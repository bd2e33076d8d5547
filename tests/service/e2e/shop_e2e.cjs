// The shopper's pages in headless Chromium (playwright-core): on the upload page a video is picked
// and sent (the progress bar reaches 100 %), the status page follows the stages to the end and opens
// the try-on page, whose canvas shows the head (non-background pixels over most of the middle) with
// the glasses (dark rim pixels where the eyes are), and turns to another view from the slider; a
// wrong token shows the API's error and no picture.
// Usage: node shop_e2e.cjs URL WORK CHROMIUM VIDEO (WORK holds node_modules and screens/).
"use strict";
const fs = require("fs");
const path = require("path");
const [, , url, work, chromiumPath, video] = process.argv;
const { chromium } = require(path.join(work, "node_modules", "playwright-core"));

const screens = path.join(work, "screens");
let failures = 0;
const check = (cond, name) => {
  if (cond) console.log(`ok - ${name}`);
  else { failures++; console.log(`not ok - ${name}`); }
};

// Pixel statistics of the try-on canvas: the share of non-white pixels in the middle third, and the
// dark pixels (the rims: darker than any skin or room) in the band of the eyes (rows 30-60 %).
function canvasStats() {
  const c = document.getElementById("view");
  const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
  let middle = 0, headPx = 0, dark = 0;
  for (let y = 0; y < c.height; y++)
    for (let x = 0; x < c.width; x++) {
      const i = 4 * (y * c.width + x), r = d[i], g = d[i + 1], b = d[i + 2];
      const inMiddle = x > c.width / 3 && x < (2 * c.width) / 3 && y > c.height / 3 && y < (2 * c.height) / 3;
      if (inMiddle) { middle++; if (Math.min(r, g, b) < 230) headPx++; }
      if (y > 0.3 * c.height && y < 0.6 * c.height && Math.max(r, g, b) < 80) dark++;
    }
  return { width: c.width, height: c.height, head: headPx / middle, dark, url: c.toDataURL("image/png").length };
}

(async () => {
  const browser = await chromium.launch({ executablePath: chromiumPath, args: ["--no-sandbox"] });
  const page = await browser.newPage({ viewport: { width: 420, height: 900 } });
  page.on("pageerror", (e) => { failures++; console.log(`not ok - page error: ${e.message}`); });
  try {
    await page.goto(url);
    await page.setInputFiles("#pick", video);
    check(await page.isEnabled("#send"), "upload page: picking a video enables the button");
    await page.evaluate(() => {
      // Keep the bar's highest value across the navigation that follows the upload.
      const bar = document.getElementById("bar");
      const native = Object.getOwnPropertyDescriptor(HTMLProgressElement.prototype, "value");
      Object.defineProperty(bar, "value", {
        get() { return native.get.call(bar); },
        set(v) { native.set.call(bar, v); sessionStorage.setItem("bar", String(native.get.call(bar))); },
      });
    });
    const t0 = Date.now();
    await page.click("#send");
    await page.waitForURL(/status\.html#id=/, { timeout: 30000 });
    check(Number(await page.evaluate(() => sessionStorage.getItem("bar"))) === 100, "upload page: the progress bar reached 100 %");
    const fragment = new URLSearchParams(new URL(page.url()).hash.slice(1));
    fs.writeFileSync(path.join(work, "token"), fragment.get("token"));
    const stages = new Set();
    const deadline = Date.now() + 480000;  // minutes on a loaded 2-core machine
    while (!page.url().includes("tryon.html") && Date.now() < deadline) {
      const text = await page.textContent("#stage").catch(() => "");
      if (text) stages.add(text.replace(/ \(\d+ %\)/, ""));
      const err = await page.isVisible("#error").catch(() => false);
      if (err) { console.log(`# status error: ${await page.textContent("#error")}`); }
      await page.waitForTimeout(250);
    }
    console.log(`# stages seen: ${JSON.stringify([...stages])}; upload to try-on page ${(Date.now() - t0) / 1000} s`);
    check(page.url().includes("tryon.html"), "status page: follows the job to the try-on page");
    check([...stages].some((s) => /3D head/.test(s)), "status page: showed the training stage");
    await page.waitForFunction(() => document.body.dataset.ready === "1", null, { timeout: 30000 });
    const s0 = await page.evaluate(canvasStats);
    console.log(`# view 0: ${JSON.stringify(s0)}`);
    await page.screenshot({ path: path.join(screens, "tryon.png") });
    check(s0.width === 192 && s0.height === 192, "try-on page: the view is the job's 192x192 picture");
    check(s0.head > 0.6, "try-on page: the head covers the middle of the view");
    check(s0.dark >= 20, "try-on page: the glasses' rims are there");
    await page.fill("#angle", "1");
    await page.dispatchEvent("#angle", "input");
    const s1 = await page.evaluate(canvasStats);
    check(s1.url !== s0.url && (await page.evaluate(() => document.body.dataset.shown)).endsWith("#1"),
          "try-on page: the slider turns to another view");
    const wrong = page.url().replace(/token=[0-9a-f]+/, "token=" + "0".repeat(64));
    await page.goto("about:blank");
    await page.goto(wrong);
    await page.waitForSelector("#error:not([hidden])", { timeout: 10000 });
    check(/no capture with this id and token/.test(await page.textContent("#error")),
          "try-on page: a wrong token shows the API's error and no picture");
  } catch (e) {
    failures++;
    console.log(`not ok - ${e.message}`);
    await page.screenshot({ path: path.join(screens, "failure.png") }).catch(() => {});
  }
  await browser.close();
  process.exit(failures ? 1 : 0);
})();
