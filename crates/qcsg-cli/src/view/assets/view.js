// The preview page of `qcsg view` and of the VS Code preview panel: shows frames of the solid,
// turns, pans and zooms the camera, lists the diagnostics and asks which call made a pixel.
//
// Where frames come from is the host's business: over HTTP from `qcsg view` (the default host
// below), or, in VS Code, through the extension and the language server (the panel defines
// `window.qcsgHost` before this script runs). A host has:
//   frame(params)  -> Promise<{url, ms, renderer?}>   an image URL for {width, height, camera,
//                     projection}, the render time and the renderer, when it says
//   pick(params)   -> Promise<object|null> what pixel {x, y} of that frame shows
//   camera(params) -> Promise<{eye, center, radius}> the eye and centre of a (named) view
//   subscribe(fn)  -> calls fn(changeEvent) for each rebuilt scene
//   reveal(place)  -> goes to a place in the sources ({file, range, byte_range})
//   renderer       -> a word for the status line
// Only one frame is ever in flight: while it renders, later camera moves only replace the
// wanted parameters, and the latest wanted frame is asked for once it returns.
"use strict";

(function () {
  const SMALL = 4; // while dragging, frames are this many times smaller in each direction
  const FOV = 30; // degrees, as the renderer's perspective camera
  const $ = (id) => document.getElementById(id);
  // The status line's words for the server's `x-qcsg-renderer`.
  const RENDERERS = { raytrace: "CPU ray tracer", splat: "splat renderer" };

  function httpHost() {
    const query = (params) =>
      Object.entries(params)
        .map(([k, v]) => `${encodeURIComponent(k)}=${encodeURIComponent(v)}`)
        .join("&");
    const answer = async (response) => {
      if (response.ok) return response;
      let message = `${response.status}`;
      try {
        message = (await response.json()).error.message;
      } catch (_) {
        /* not JSON */
      }
      throw new Error(message);
    };
    return {
      renderer: "CPU ray tracer",
      async frame(params) {
        const response = await answer(await fetch(`frame.png?${query(params)}`));
        const blob = await response.blob();
        return {
          url: URL.createObjectURL(blob),
          ms: Number(response.headers.get("x-qcsg-render-ms")),
          renderer: RENDERERS[response.headers.get("x-qcsg-renderer")],
        };
      },
      async pick(params) {
        return (await answer(await fetch(`pick?${query(params)}`))).json();
      },
      async camera(params) {
        return (await answer(await fetch(`camera?${query(params)}`))).json();
      },
      subscribe(onChange) {
        const source = new EventSource("events");
        source.addEventListener("change", (e) => onChange(JSON.parse(e.data)));
        source.onerror = () => setStatus("disconnected: is `qcsg view` still running?");
      },
      reveal(place) {
        showPlace(place);
      },
    };
  }

  const host = window.qcsgHost || httpHost();
  const image = $("frame");
  const viewport = $("viewport");
  const state = {
    view: "iso", // a named view, or null when `eye`/`center` hold an explicit camera
    eye: null,
    center: null,
    radius: 1,
    projection: "perspective",
    fitted: null, // the named view's camera, to start turning it from
    change: null, // the latest change event
    frames: 0, // frames shown, for tests and the status line
    highlight: null, // quadrics to tint (the editor's cursor), passed to hosts that can
  };
  let inFlight = false;
  let wanted = null; // the parameters of the frame to show next, if not yet asked for
  let lastUrl = null;
  let settle = null;

  function setStatus(text) {
    $("status").textContent = text;
  }

  function frameSize(small) {
    const scale = small ? SMALL : 1;
    const width = Math.max(1, Math.ceil(viewport.clientWidth / scale));
    const height = Math.max(1, Math.ceil(viewport.clientHeight / scale));
    return { width, height };
  }

  function cameraText() {
    if (state.view) return state.view;
    return [...state.eye, ...state.center].map((v) => +v.toPrecision(12)).join(",");
  }

  function params(small) {
    const p = { ...frameSize(small), camera: cameraText(), projection: state.projection };
    if (state.highlight && host.highlights) p.highlight = state.highlight;
    return p;
  }

  // Asks for the frame of `p` now, or after the one in flight (replacing any queued one).
  function requestFrame(small) {
    if (!state.change || state.change.image_generation == null) return;
    wanted = params(small);
    if (!inFlight) next();
  }

  async function next() {
    const p = wanted;
    wanted = null;
    if (!p) return;
    inFlight = true;
    const started = performance.now();
    try {
      const frame = await host.frame(p);
      await new Promise((resolve) => {
        image.onload = resolve;
        image.onerror = resolve;
        image.src = frame.url;
      });
      if (lastUrl && lastUrl.startsWith("blob:")) URL.revokeObjectURL(lastUrl);
      lastUrl = frame.url;
      state.frames += 1;
      document.body.dataset.frames = state.frames;
      document.body.dataset.frameWidth = p.width;
      const total = performance.now() - started;
      setStatus(
        `${frame.renderer || host.renderer} · ${p.width}×${p.height} · render ${frame.ms ? frame.ms.toFixed(0) : "?"} ms` +
          ` (${total.toFixed(0)} ms in all)` +
          (state.change && state.change.quadrics != null ? ` · ${state.change.quadrics} quadrics` : ""),
      );
    } catch (error) {
      setStatus(`no frame: ${error.message}`);
    } finally {
      inFlight = false;
      if (wanted) next();
    }
  }

  async function fit() {
    if (!state.view || !state.change || state.change.image_generation == null) return;
    try {
      const camera = await host.camera({ ...frameSize(false), camera: state.view, projection: state.projection });
      state.fitted = camera;
      state.radius = camera.radius;
    } catch (_) {
      state.fitted = null;
    }
  }

  // The camera as an explicit eye and centre (from the fitted named view when there is one).
  function explicit() {
    if (state.view) {
      if (!state.fitted) return false;
      state.eye = state.fitted.eye.slice();
      state.center = state.fitted.center.slice();
      state.view = null;
      markView();
    }
    return true;
  }

  const sub = (a, b) => a.map((v, i) => v - b[i]);
  const add = (a, b) => a.map((v, i) => v + b[i]);
  const scale = (a, s) => a.map((v) => v * s);
  const norm = (a) => Math.hypot(...a);
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const unit = (a) => scale(a, 1 / (norm(a) || 1));

  function orbit(from, dx, dy) {
    const d = sub(from.eye, from.center);
    const r = norm(d);
    let azimuth = Math.atan2(d[1], d[0]) - dx * 0.01;
    let elevation = Math.asin(Math.max(-1, Math.min(1, d[2] / r))) + dy * 0.01;
    const limit = (89 * Math.PI) / 180;
    elevation = Math.max(-limit, Math.min(limit, elevation));
    const offset = [
      r * Math.cos(elevation) * Math.cos(azimuth),
      r * Math.cos(elevation) * Math.sin(azimuth),
      r * Math.sin(elevation),
    ];
    state.eye = add(from.center, offset);
    state.center = from.center.slice();
  }

  function pan(from, dx, dy) {
    const forward = unit(sub(from.center, from.eye));
    const right = unit(cross(forward, Math.abs(forward[2]) > 0.999999 ? [0, 1, 0] : [0, 0, 1]));
    const up = cross(right, forward);
    const distance = norm(sub(from.center, from.eye));
    const halfHeight =
      state.projection === "ortho" ? 1.1 * state.radius : distance * Math.tan(((FOV / 2) * Math.PI) / 180);
    const perPixel = (2 * halfHeight) / Math.max(1, viewport.clientHeight);
    const move = add(scale(right, -dx * perPixel), scale(up, dy * perPixel));
    state.eye = add(from.eye, move);
    state.center = add(from.center, move);
  }

  function zoom(factor) {
    if (!explicit()) return;
    const d = sub(state.eye, state.center);
    const length = Math.max(norm(d) * factor, 1e-9 * (state.radius || 1));
    state.eye = add(state.center, scale(unit(d), length));
  }

  let drag = null;
  viewport.addEventListener("contextmenu", (e) => e.preventDefault());
  viewport.addEventListener("pointerdown", (e) => {
    viewport.setPointerCapture(e.pointerId);
    drag = { x: e.clientX, y: e.clientY, button: e.button, shift: e.shiftKey, moved: false, from: null };
  });
  viewport.addEventListener("pointermove", (e) => {
    if (!drag) return;
    const dx = e.clientX - drag.x;
    const dy = e.clientY - drag.y;
    if (!drag.moved && Math.hypot(dx, dy) < 4) return;
    if (!drag.moved) {
      if (!explicit()) return;
      drag.moved = true;
      drag.from = { eye: state.eye.slice(), center: state.center.slice() };
      viewport.classList.add("dragging");
    }
    if (drag.button === 0 && !drag.shift) orbit(drag.from, dx, dy);
    else pan(drag.from, dx, dy);
    requestFrame(true);
  });
  viewport.addEventListener("pointerup", (e) => {
    if (!drag) return;
    const wasDrag = drag.moved;
    drag = null;
    viewport.classList.remove("dragging");
    if (wasDrag) requestFrame(false);
    else if (e.button === 0) pickAt(e);
  });
  viewport.addEventListener(
    "wheel",
    (e) => {
      e.preventDefault();
      zoom(Math.exp(Math.max(-200, Math.min(200, e.deltaY)) * 0.002));
      requestFrame(true);
      clearTimeout(settle);
      settle = setTimeout(() => requestFrame(false), 200);
    },
    { passive: false },
  );
  window.addEventListener("resize", () => {
    clearTimeout(settle);
    settle = setTimeout(() => {
      fit();
      requestFrame(false);
    }, 150);
  });

  function markView() {
    for (const button of document.querySelectorAll("[data-view]")) {
      button.classList.toggle("active", button.dataset.view === state.view);
    }
    $("projection").textContent = state.projection === "ortho" ? "orthographic" : "perspective";
  }

  for (const button of document.querySelectorAll("[data-view]")) {
    button.addEventListener("click", async () => {
      state.view = button.dataset.view;
      markView();
      requestFrame(false);
      await fit();
    });
  }
  $("projection").addEventListener("click", async () => {
    state.projection = state.projection === "ortho" ? "perspective" : "ortho";
    markView();
    requestFrame(false);
    await fit();
  });

  // `file:line:column`, one-based, with the file's own name (the whole path is the link's title).
  function location(place, whole) {
    const file = whole ? place.file : place.file.split(/[\\/]/).pop();
    return `${file}:${place.range.start.line + 1}:${place.range.start.character + 1}`;
  }

  // Shows a place in the side panel (the browser cannot open the editor).
  function showPlace(place) {
    $("pick").dataset.revealed = location(place, true);
  }

  function link(place) {
    const a = document.createElement("a");
    a.className = "place";
    a.textContent = location(place);
    a.title = location(place, true);
    a.addEventListener("click", (e) => {
      e.preventDefault();
      host.reveal(place);
    });
    return a;
  }

  async function pickAt(e) {
    if (!state.change || state.change.image_generation == null) return;
    const p = params(false);
    const rect = image.getBoundingClientRect();
    p.x = Math.min(p.width - 1, Math.max(0, Math.floor(((e.clientX - rect.left) * p.width) / rect.width)));
    p.y = Math.min(p.height - 1, Math.max(0, Math.floor(((e.clientY - rect.top) * p.height) / rect.height)));
    const panel = $("pick");
    try {
      const picked = await host.pick(p);
      panel.replaceChildren();
      if (!picked) {
        panel.textContent = "Background: no part there.";
        delete panel.dataset.file;
        delete panel.dataset.line;
        return;
      }
      if (!picked.file) {
        panel.textContent = `A face where the ${picked.layer} is cut off (term ${picked.term}).`;
        return;
      }
      panel.dataset.file = picked.file;
      panel.dataset.line = picked.range.start.line + 1;
      panel.append(link(picked), document.createElement("br"));
      const what = document.createElement("span");
      what.textContent = `${picked.layer}, quadric ${picked.quadric}, term ${picked.term}`;
      panel.append(what);
      if (picked.chain.length) {
        const chain = document.createElement("div");
        chain.className = "chain";
        chain.append("called through ");
        picked.chain.forEach((call, i) => {
          if (i) chain.append(" → ");
          chain.append(`${call.module}() at `, link(call));
        });
        panel.append(chain);
      }
      host.reveal(picked);
    } catch (error) {
      panel.textContent = `Pick failed: ${error.message}`;
    }
  }

  function showChange(change) {
    state.change = change;
    document.body.dataset.generation = change.generation;
    document.body.dataset.ok = change.ok;
    const list = $("diagnostics");
    list.replaceChildren();
    for (const d of change.diagnostics || []) {
      const item = document.createElement("li");
      item.className = d.severity;
      item.append(link(d), ` ${d.severity} ${d.code}: ${d.message}`);
      list.append(item);
    }
    const errors = (change.diagnostics || []).filter((d) => d.severity === "error").length;
    $("count").textContent = change.diagnostics && change.diagnostics.length ? `(${change.diagnostics.length})` : "";
    if (change.file) {
      $("title").textContent = change.file.split(/[\\/]/).pop();
      $("title").title = change.file;
      document.title = `${change.file} — qcsg view`;
    }
    const banner = $("banner");
    const stale = !change.ok;
    image.classList.toggle("stale", stale);
    banner.hidden = !stale;
    if (stale) {
      const reason = change.error || `${errors} error${errors === 1 ? "" : "s"}`;
      banner.textContent =
        change.image_generation == null
          ? `${reason}: nothing to show yet.`
          : `${reason}: showing the last version that compiled.`;
      return;
    }
    fit().then(() => requestFrame(false));
  }

  window.qcsgView = {
    // For the editor: tint the parts made by these quadrics (null: none).
    highlight(quadrics) {
      state.highlight = quadrics && quadrics.length ? quadrics.join(",") : null;
      requestFrame(false);
    },
    state,
  };
  markView();
  host.subscribe(showChange);
})();
