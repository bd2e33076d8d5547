// The upload page: create a capture, send the video with a progress bar (XMLHttpRequest reports the
// upload's progress, fetch does not), start the job, then go to the status page with the capture's
// id and token in the fragment.
"use strict";
(function () {
  const $ = (id) => document.getElementById(id);
  let file = null;
  for (const input of [$("record"), $("pick")]) {
    input.addEventListener("change", () => {
      file = input.files[0] || null;
      $("chosen").textContent = file ? file.name + " (" + (file.size / 1048576).toFixed(1) + " MB)" : "";
      $("send").disabled = !file;
    });
  }

  function putVideo(c, f) {
    return new Promise((resolve, reject) => {
      const xhr = new XMLHttpRequest();
      xhr.open("PUT", "/api/v1/captures/" + c.id + "/video");
      xhr.setRequestHeader("Authorization", "Bearer " + c.token);
      xhr.upload.onprogress = (e) => {
        if (e.lengthComputable) $("bar").value = (100 * e.loaded) / e.total;
      };
      // A fast upload may end without a progress event: its end fills the bar.
      xhr.upload.onload = () => { $("bar").value = 100; };
      xhr.onload = () => {
        if (xhr.status >= 200 && xhr.status < 300) return resolve();
        let msg = "the upload was refused (" + xhr.status + ")";
        try { msg = JSON.parse(xhr.responseText).error.message; } catch (e) { /* not JSON */ }
        reject(new Error(msg));
      };
      xhr.onerror = () => reject(new Error("the connection broke during the upload: try again"));
      xhr.send(f);
    });
  }

  $("send").addEventListener("click", async () => {
    $("send").disabled = true;
    $("error").hidden = true;
    $("bar").hidden = false;
    try {
      $("said").textContent = "Preparing…";
      const r = await fetch("/api/v1/captures", { method: "POST" });
      if (!r.ok) throw new Error((await r.json()).error.message);
      const c = await r.json();
      $("said").textContent = "Uploading…";
      await putVideo(c, file);
      $("said").textContent = "Starting…";
      await shopFetch(c, "/api/v1/captures/" + c.id + "/start", { method: "POST" });
      location.href = shopLink("/status.html", c);
    } catch (e) {
      shopShowError($("error"), e.message);
      $("send").disabled = false;
    }
  });
})();
