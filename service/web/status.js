// The status page: polls the capture's job once a second (its token from the fragment) and shows its
// stage, progress and ETA, the product's own message when it fails, and the try-on link (followed
// at once) when it is finished.
"use strict";
(function () {
  const $ = (id) => document.getElementById(id);
  const words = { capture: "Finding the camera of every frame", train: "Building your 3D head",
                  fit: "Placing every frame of the catalogue" };
  const c = shopCapture();
  if (!c) return shopShowError($("error"), "This link is incomplete: open the link you got after the upload.");

  async function poll() {
    let st;
    try {
      st = await (await shopFetch(c, "/api/v1/captures/" + c.id)).json();
    } catch (e) {
      shopShowError($("error"), e.message);
      return setTimeout(poll, 3000);
    }
    $("error").hidden = true;
    $("bar").value = st.progress;
    const stage = words[st.stage] || "Waiting for a free worker";
    $("stage").textContent = st.state === "queued" ? "In the queue…" : stage + " (" + Math.round(st.progress) + " %)";
    $("eta").textContent = st.eta_seconds != null ? "About " + Math.ceil(st.eta_seconds / 60) + " min left" : "";
    if (st.state === "failed") {
      $("stage").textContent = "It did not work this time.";
      return shopShowError($("error"), st.message);
    }
    if (st.state === "finished") {
      $("stage").textContent = "Ready.";
      $("tryon").href = shopLink("/tryon.html", c);
      $("done").hidden = false;
      location.href = $("tryon").href;
      return;
    }
    setTimeout(poll, 1000);
  }
  poll();
})();
