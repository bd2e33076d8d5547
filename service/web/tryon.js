// The try-on page: the finished job's views of every catalogue frame on the shopper's head (rendered
// once by the job, served behind the capture's token; frames that could not be fitted listed with
// the reason, frames added since being fitted), one frame at a time, turned by dragging or
// the slider; the frame's placement and the picture shown can be downloaded. Images are fetched with
// the token and drawn from blob URLs (same origin, so the canvas stays readable).
"use strict";
(function () {
  const $ = (id) => document.getElementById(id);
  const c = shopCapture();
  const canvas = $("view"), ctx = canvas.getContext("2d");
  let views = {}, fits = {}, frame = "", images = [], index = 0;
  if (!c) return shopShowError($("error"), "This link is incomplete: open the link you got after the upload.");
  const base = "/api/v1/captures/" + c.id + "/artifacts/";

  async function blobUrl(path) {
    return URL.createObjectURL(await (await shopFetch(c, base + path)).blob());
  }
  function loadImage(url) {
    return new Promise((resolve, reject) => {
      const img = new Image();
      img.onload = () => resolve(img);
      img.onerror = () => reject(new Error("a try-on picture could not be read"));
      img.src = url;
    });
  }
  function show(i) {
    if (!images.length) return;
    index = ((i % images.length) + images.length) % images.length;
    const img = images[index];
    canvas.width = img.naturalWidth, canvas.height = img.naturalHeight;
    ctx.drawImage(img, 0, 0);
    $("angle").value = index;
    $("image").href = img.src;
    document.body.dataset.shown = frame + "#" + index;
  }
  async function choose(name) {
    frame = name;
    for (const b of document.querySelectorAll("button.frame")) b.classList.toggle("on", b.textContent === name);
    const urls = await Promise.all(views[name].map(blobUrl));
    images = await Promise.all(urls.map(loadImage));
    $("angle").max = images.length - 1;
    $("placement").href = await blobUrl(fits[name]);
    show(0);
  }

  let dragX = null;
  canvas.addEventListener("pointerdown", (e) => { dragX = e.clientX; canvas.setPointerCapture(e.pointerId); });
  canvas.addEventListener("pointerup", () => { dragX = null; });
  canvas.addEventListener("pointermove", (e) => {
    if (dragX === null) return;
    const step = canvas.clientWidth / Math.max(images.length, 1) / 2;
    if (Math.abs(e.clientX - dragX) >= step) {
      show(index + (e.clientX > dragX ? 1 : -1));
      dragX = e.clientX;
    }
  });
  $("angle").addEventListener("input", () => show(Number($("angle").value)));

  // One button per fitted frame; a frame that could not be fitted is shown disabled with the
  // reason, and frames added to the catalogue since the job finished as being fitted.
  function listFrames(a) {
    views = a.views || {};
    fits = a.fits || {};
    $("frames").textContent = "";
    for (const name of Object.keys(views)) {
      const b = document.createElement("button");
      b.className = "frame";
      b.textContent = name;
      b.addEventListener("click", () => choose(name).catch((e) => shopShowError($("error"), e.message)));
      $("frames").appendChild(b);
    }
    const off = Object.entries(a.unavailable || {}).map(([name, why]) => [name, "unavailable: " + why]);
    for (const name of a.pending || []) off.push([name, "being fitted to your head, shown in a minute"]);
    for (const [name, why] of off) {
      const b = document.createElement("button");
      b.className = "frame unavailable";
      b.disabled = true;
      b.textContent = name;
      b.title = why;
      $("frames").appendChild(b);
    }
    $("unavailable").textContent = off.map(([name, why]) => name + ": " + why).join("\n");
    $("unavailable").hidden = !off.length;
  }
  async function job() {
    return (await shopFetch(c, "/api/v1/captures/" + c.id)).json();
  }
  // While frames added to the catalogue are fitted, the page asks again every 2 s.
  async function follow(st) {
    if (st.state === "finished") return;
    while (st.state === "queued" || st.state === "running") {
      await new Promise((r) => setTimeout(r, 2000));
      st = await job();
    }
    if (st.state !== "finished") throw new Error(st.message || "the new frames could not be fitted");
    listFrames(st.artifacts);
    if (frame && views[frame]) await choose(frame);
  }

  (async () => {
    try {
      const st = await job();
      const names = Object.keys((st.artifacts || {}).views || {});
      if (st.state !== "finished" && !names.length) {
        location.href = shopLink("/status.html", c);
        return;
      }
      listFrames(st.artifacts);
      if (!names.length) throw new Error("The shop has no frames to try on yet.");
      await choose(names[0]);
      document.body.dataset.ready = "1";
      await follow(st);
    } catch (e) {
      shopShowError($("error"), e.message);
    }
  })();
})();
