// The try-on page: the finished job's views of every catalogue frame on the shopper's head (rendered
// once by the job, served behind the capture's token), one frame at a time, turned by dragging or
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

  (async () => {
    try {
      const st = await (await shopFetch(c, "/api/v1/captures/" + c.id)).json();
      if (st.state !== "finished") {
        location.href = shopLink("/status.html", c);
        return;
      }
      views = st.artifacts.views || {};
      fits = st.artifacts.fits || {};
      const names = Object.keys(views);
      if (!names.length) throw new Error("The shop has no frames to try on yet.");
      for (const name of names) {
        const b = document.createElement("button");
        b.className = "frame";
        b.textContent = name;
        b.addEventListener("click", () => choose(name).catch((e) => shopShowError($("error"), e.message)));
        $("frames").appendChild(b);
      }
      await choose(names[0]);
      document.body.dataset.ready = "1";
    } catch (e) {
      shopShowError($("error"), e.message);
    }
  })();
})();
