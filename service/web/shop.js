// Shared by the shopper's pages: the capture's id and token from the URL fragment (browsers never
// send the fragment to the server, so the token stays out of access logs and Referer headers), and
// API calls that carry the token as "Authorization: Bearer".
"use strict";

function shopCapture() {
  const f = new URLSearchParams(location.hash.slice(1));
  const id = f.get("id") || "", token = f.get("token") || "";
  return /^[0-9a-f]{32}$/.test(id) && token ? { id, token } : null;
}

function shopLink(page, c) {
  return page + "#id=" + encodeURIComponent(c.id) + "&token=" + encodeURIComponent(c.token);
}

// fetch() with the token; resolves to the Response, throws the API's error message on a non-2xx.
async function shopFetch(c, path, init) {
  const opts = Object.assign({}, init || {});
  opts.headers = Object.assign({ Authorization: "Bearer " + c.token }, opts.headers || {});
  const r = await fetch(path, opts);
  if (!r.ok) {
    let msg = "the server answered " + r.status;
    try { msg = (await r.json()).error.message; } catch (e) { /* not JSON */ }
    throw new Error(msg);
  }
  return r;
}

function shopShowError(el, text) {
  el.textContent = text;
  el.hidden = false;
}
