// The blurlab session client: what the server chose, shown; what the subject pressed, reported.
// The server runs the session (docs/web.md); this page follows its State: display check, then
// instructions, practice and main trials, breaks and the end. Nothing the page receives tells the
// level or which pair differs.

import { Api, ApiError } from "./api.js";
import {
  blindSpotMethod,
  cardMethod,
  config,
  measureRefresh,
  pixelsPerDegree,
} from "./calibrate.js";
import { closeAll, decodeFrame, decoders, drawPairs, play, prime, tooSmall } from "./trial.js";
import { VideoStore } from "./videos.js";
import { fitCanvas, windowDevicePx } from "./canvas.js";
import { message, nextKey, setScreen, sleep } from "./ui.js";

const HEARTBEAT_MS = 5000;
const FEEDBACK_MS = 1000;
const LEAVE_GUARD_MS = 800;
const ELSEWHERE = "This session is open in another tab or window. Continue there, or close that " +
  "one and reload this page after 20 seconds.";

const canvas = document.getElementById("canvas");
let fullscreen = false;
let refreshMs = null;
let stopped = false;
// The trial whose videos are at hand, for the read-back test hook.
let loaded = null;
// The session's encoded videos.
let store = null;

/** What the page needs; the names of the missing features. */
function browserCheck() {
  const missing = [];
  const c = document.createElement("canvas");
  if (!c.getContext || !c.getContext("2d")) missing.push("canvas 2D");
  if (typeof createImageBitmap !== "function") missing.push("createImageBitmap");
  if (typeof requestAnimationFrame !== "function") missing.push("requestAnimationFrame");
  if (!window.performance || typeof performance.now !== "function") missing.push("performance.now");
  if (typeof KeyboardEvent === "undefined" || !("key" in KeyboardEvent.prototype)) {
    missing.push("keyboard events (KeyboardEvent.key)");
  }
  if (typeof fetch !== "function") missing.push("fetch");
  return missing;
}

/** This tab's id: kept across reloads of the tab (sessionStorage), new in another tab. */
function tabId() {
  let id = sessionStorage.getItem("blurlab-tab");
  if (!id) {
    const b = new Uint8Array(16);
    crypto.getRandomValues(b);
    id = Array.from(b, (x) => x.toString(16).padStart(2, "0")).join("");
    sessionStorage.setItem("blurlab-tab", id);
  }
  return id;
}

function stop(name, title, text) {
  stopped = true;
  message(name, title, text);
}

/** Wait for Space; the key press is a user gesture, so full screen can be asked for here. */
async function welcome() {
  message(
    "welcome",
    "Welcome",
    "The experiment shows short videos in full screen. Please close other programs, sit " +
      "comfortably and keep this window in front until the end.",
    "Press Space to continue in full screen.",
  );
  await nextKey([" "]);
  try {
    await document.documentElement.requestFullscreen({ navigationUI: "hide" });
    fullscreen = document.fullscreenElement !== null;
  } catch (_) {
    fullscreen = false;
  }
  // Let the window settle at its new size.
  await sleep(300);
}

/** The consent text (the experimenter's, shown as text); Y agrees, N declines. */
async function consent(api, state) {
  message("consent", "Consent", state.message || "", "Press Y to agree and take part, N to decline.");
  const e = await nextKey(["y", "Y", "n", "N"]);
  return api.consent(e.key.toLowerCase() === "y");
}

/** The end (done or screened out): the text, then the platform's URL when there is one. */
async function leave(state, name, title) {
  if (!state.redirect) {
    stop(name, title, state.message || "");
    return state;
  }
  message(name, title, state.message || "", "Press Space to return to the study platform.");
  // A key still pressed for the screen before (the blind spot's Space) must not skip this one.
  await sleep(LEAVE_GUARD_MS);
  await nextKey([" "]);
  stopped = true;
  location.assign(state.redirect);
  return state;
}

/** Calibrate, check that the trial fits, post the display facts; returns the new State. */
async function displayCheck(api, state) {
  const pxPerMm = await cardMethod();
  const distMm = await blindSpotMethod(canvas, pxPerMm);
  if (!(await waitUntilFits(state, true))) return api.screenOut("window_too_small");
  refreshMs = await measureRefresh();
  const dpr = window.devicePixelRatio || 1;
  const facts = {
    screen_px: [Math.round(screen.width * dpr), Math.round(screen.height * dpr)],
    window_px: windowDevicePx(),
    device_pixel_ratio: dpr,
    px_per_mm: pxPerMm,
    viewing_distance_mm: distMm,
    pixels_per_degree: pixelsPerDegree(pxPerMm, distMm),
    refresh_interval_ms: refreshMs,
    user_agent: navigator.userAgent,
    fullscreen,
  };
  return api.display(facts);
}

/** Stop with a message while the window is smaller than the trial at 1:1; with `mayLeave`
 *  (before the first trial) Q gives up: resolves false. */
async function waitUntilFits(state, mayLeave = false) {
  for (;;) {
    const text = tooSmall(state);
    if (text === null) return true;
    const hint = mayLeave ? "If you cannot enlarge it, press Q to leave the study." : "";
    message("too-small", "The window is too small", text, hint);
    const resized = new Promise((r) => window.addEventListener("resize", () => r(true), { once: true }));
    const quit = mayLeave ? nextKey(["q", "Q"]).then(() => false) : new Promise(() => {});
    if (!(await Promise.race([resized, quit]))) return false;
  }
}

async function instructions(api, state) {
  const resumed = state.progress.done + state.progress.practice_done > 0;
  const lead = resumed
    ? `Welcome back. ${state.progress.done} of ${state.progress.planned} trials are done; the ` +
      "session continues where it stopped.\n\n"
    : "";
  const [k1, k2] = [state.keys.pair1, state.keys.pair2].map((k) => k.map(keyName).join(" or "));
  const text =
    state.message ||
    "Each trial shows two pairs of videos, one pair after the other. In one pair the two " +
      "videos differ; in the other they are the same. Say which pair differed: press " +
      `${k1} for the first pair, ${k2} for the second.` +
      (state.progress.practice_planned > state.progress.practice_done
        ? " A few practice trials come first."
        : "");
  message("instructions", "Instructions", lead + text, "Press Space to start.");
  await nextKey([" "]);
  return api.advance("instructions");
}

function keyName(k) {
  return { ArrowLeft: "Left arrow", ArrowRight: "Right arrow", " ": "Space" }[k] || k;
}

async function breakScreen(api, state) {
  const p = state.progress;
  message(
    "break",
    "Break",
    state.message || `${p.done} of ${p.planned} trials done. Rest your eyes as long as you like.`,
    "Press Space to continue.",
  );
  await nextKey([" "]);
  return api.advance("break");
}

/** The trial's videos (fetched now unless fetched ahead) and pair 1's first frames decoded;
 *  returns {packs, first, ms}: ms is the wait before the trial can start. */
async function prepare(state) {
  const t0 = performance.now();
  const ids = [...new Set(state.trial.pairs.flat())];
  store.pin([...ids, ...state.ahead]);
  const got = await Promise.all(ids.map((id) => store.get(id)));
  store.want(state.ahead);
  const packs = new Map(ids.map((id, k) => [id, got[k]]));
  const first = decoders(state, packs, state.playback.layout === "sequential" ? [0] : [0, 1]);
  try {
    await prime(first);
  } catch (e) {
    closeAll(first);
    throw e;
  }
  return { packs, first, ms: performance.now() - t0 };
}

/** Fetch, decode, play, take the key, post the answer until acknowledged; returns the State. */
async function trial(api, state) {
  await waitUntilFits(state);
  const t = state.trial;
  message("preload", t.practice ? "Practice" : "Next trial", "Loading the videos…");
  const { packs, first, ms } = await prepare(state);
  loaded = { state, packs };
  document.body.dataset.fetchedBytes = String(store.fetchedBytes);
  document.body.dataset.fetches = String(store.fetches);
  try {
    if (refreshMs === null) refreshMs = await measureRefresh(30);
    setScreen("trial");
    const timing = await play(canvas, state, packs, first, refreshMs);
    const keys = [...state.keys.pair1, ...state.keys.pair2];
    document.body.dataset.trial = `${t.practice ? "p" : "m"}${t.index}`;
    message("respond", "Which pair differed?", "", hintFor(state));
    const e = await nextKey(keys);
    const response = state.keys.pair1.includes(e.key) ? 1 : 2;
    const answer = {
      session: state.session,
      practice: t.practice,
      trial: t.index,
      response,
      timing: {
        rt_ms: e.timeStamp - timing.respondAt,
        onsets_ms: timing.onsets_ms,
        frame_times_ms: timing.frame_times_ms,
        dropped_frames: timing.dropped_frames,
        late_frames: timing.late_frames,
        refresh_interval_ms: timing.refresh_interval_ms,
        preload_ms: ms,
      },
    };
    message("saving", "Saving your answer…", "");
    const reply = await api.answer(answer);
    if (reply.feedback) {
      message("feedback", reply.feedback.correct ? "Correct" : "Not correct", "");
      await sleep(FEEDBACK_MS);
    }
    return reply.state;
  } finally {
    loaded = null;
    closeAll(first);
  }
}

function hintFor(state) {
  const k1 = state.keys.pair1.map(keyName).join(" or ");
  const k2 = state.keys.pair2.map(keyName).join(" or ");
  return `Press ${k1} for the first pair, ${k2} for the second.`;
}

/** Keep the claim alive (it lapses after 20 s of silence) and notice a takeover. */
function heartbeat(api) {
  const beat = async () => {
    if (stopped) return;
    try {
      await api.state();
    } catch (e) {
      if (e instanceof ApiError && e.status === 409) stop("elsewhere", "Open elsewhere", ELSEWHERE);
    }
  };
  setInterval(beat, HEARTBEAT_MS);
}

async function run() {
  const token = location.pathname.split("/").filter(Boolean)[1] || "";
  const missing = browserCheck();
  if (missing.length > 0) {
    stop(
      "unsupported",
      "This browser cannot run the session",
      `It lacks: ${missing.join(", ")}. Please use a current Chrome, Edge, Firefox or Safari.`,
    );
    return;
  }
  const api = new Api(token, tabId(), (attempt) => {
    document.body.dataset.retries = String(attempt);
  });
  let state;
  try {
    state = await api.claim();
  } catch (e) {
    if (e instanceof ApiError && e.status === 409) stop("elsewhere", "Open elsewhere", ELSEWHERE);
    else stop("error", "The session cannot start", e.message);
    return;
  }
  heartbeat(api);
  store = new VideoStore(api, state.client, state.video.frames);
  await store.open();
  store.want(state.ahead);
  if (!["done", "screened_out"].includes(state.phase)) await welcome();
  while (!stopped) {
    try {
      state = await step(api, state);
    } catch (e) {
      if (stopped) return;
      if (e instanceof ApiError && e.status === 409 && /another tab|elsewhere/i.test(e.message)) {
        stop("elsewhere", "Open elsewhere", ELSEWHERE);
        return;
      }
      // Anything else (e.g. an answer for a trial that is no longer current): show it briefly,
      // then follow the server's state.
      message("error", "Something went wrong", e.message, "Continuing…");
      await sleep(2000);
      state = await api.state();
    }
  }
}

async function step(api, state) {
  // At a screen, fetch what the next trials show (at a trial, once its own videos are here).
  if (state.trial === null) store.want(state.ahead);
  switch (state.phase) {
    case "consent":
      return consent(api, state);
    case "display_check":
      return displayCheck(api, state);
    case "instructions":
      return instructions(api, state);
    case "practice":
    case "main":
      return trial(api, state);
    case "break":
      return breakScreen(api, state);
    case "done":
      await store.clear();
      return leave(state, "done", "Thank you!");
    case "screened_out":
      await store.clear();
      return leave(state, "screened-out", "The study ends here");
    default:
      throw new Error(`unknown phase ${state.phase}`);
  }
}

// Hooks for the browser tests (tests/web_browser.rs): calibration settings, and drawing one frame
// of the loaded trial and holding it so the canvas can be read back.
window.blurlab = {
  config,
  /** Decode frame `n` of pair `pair` (1 or 2) of the loaded trial, draw it and keep it up;
   *  resolves to the rectangles, the canvas size, the ratio and the pair's video ids. */
  async hold(pair, n) {
    if (!loaded) return null;
    const ids = loaded.state.trial.pairs[pair - 1];
    const bitmaps = await Promise.all(ids.map((id) => decodeFrame(loaded.packs.get(id), n)));
    const ctx = fitCanvas(canvas);
    canvas.hidden = false;
    document.getElementById("panel").hidden = true;
    const rects = drawPairs(ctx, loaded.state, (_, s) => bitmaps[s], [pair - 1]);
    for (const b of bitmaps) b.close();
    setScreen("hold");
    return {
      rects: rects[pair - 1],
      canvas: [canvas.width, canvas.height],
      css: [canvas.getBoundingClientRect().width, canvas.getBoundingClientRect().height],
      dpr: window.devicePixelRatio,
      ids,
    };
  },
  /** What the video store fetched: {bytes, fetches, cache: "storage" | "memory"}. */
  fetched() {
    return { bytes: store.fetchedBytes, fetches: store.fetches, cache: store.cache ? "storage" : "memory" };
  },
};

run().catch((e) => stop("error", "The session stopped", String(e && e.message ? e.message : e)));
