// Display calibration, the "virtual chinrest" (Li, Joo, Yeatman & Reinecke 2020, Sci. Rep. 10:904):
// the card method gives device pixels per millimetre (the subject sizes an on-screen card to a real
// ISO/IEC 7810 ID-1 card, 85.60 x 53.98 mm), the blind-spot method the viewing distance (the
// blind spot's centre lies 13.5 degrees temporal of fixation, so distance = (fixation-to-dot
// distance when the dot vanishes) / tan(13.5 deg)). Everything works from the keyboard; the card
// can also be dragged by its corner.

import { fitCanvas, windowDevicePx } from "./canvas.js";
import { hidePanel, isSpace, message, setScreen } from "./ui.js";

export const CARD_MM = [85.6, 53.98];
const BLIND_SPOT_DEG = 13.5;
export const BLIND_SPOT_REPEATS = 5;
// A dot that vanishes less than this far from the cross is a mistaken press (< 12 cm distance).
const MIN_BLIND_SPOT_MM = 30;

/** Settings tests may change through `window.blurlab.config` before the calibration starts. */
export const config = { dotSpeedMmPerS: 30 };

/** Median interval between `n` animation frames, milliseconds. */
export function measureRefresh(n = 60) {
  return new Promise((resolve) => {
    const ts = [];
    const tick = (t) => {
      ts.push(t);
      if (ts.length > n) {
        const d = ts.slice(1).map((t, i) => t - ts[i]).sort((a, b) => a - b);
        resolve(d[Math.floor(d.length / 2)]);
      } else requestAnimationFrame(tick);
    };
    requestAnimationFrame(tick);
  });
}

/** The card method: resolves with device pixels per millimetre. */
export function cardMethod() {
  const dpr = window.devicePixelRatio || 1;
  message(
    "card-intro",
    "Screen size",
    "Hold a bank card, ID card or any card of that standard size (85.6 x 54 mm) flat against the " +
      "screen over the blue card and make the blue card exactly as large as yours: Right or Up " +
      "arrow makes it larger, Left or Down smaller (with Shift: in bigger steps); or drag its " +
      "white corner.",
    "Press Space to begin.",
  );
  return waitSpace().then(
    () =>
      new Promise((resolve) => {
        hidePanel();
        const area = document.getElementById("card-area");
        const card = document.getElementById("card");
        const handle = document.getElementById("card-handle");
        area.hidden = false;
        // Start at the CSS reference's 96 px per inch.
        let widthPx = Math.round(((CARD_MM[0] / 25.4) * 96) * dpr);
        const maxPx = windowDevicePx()[0] - Math.round(96 * dpr);
        const show = () => {
          widthPx = Math.max(50, Math.min(maxPx, widthPx));
          card.style.width = `${widthPx / dpr}px`;
          card.style.height = `${(widthPx * CARD_MM[1]) / CARD_MM[0] / dpr}px`;
          document.body.dataset.cardPx = String(widthPx);
        };
        show();
        setScreen("card");
        let drag = null;
        const onDown = (e) => {
          drag = { x: e.clientX, w: widthPx };
          handle.setPointerCapture(e.pointerId);
        };
        const onMove = (e) => {
          if (!drag) return;
          widthPx = Math.round(drag.w + (e.clientX - drag.x) * dpr);
          show();
        };
        const onUp = () => {
          drag = null;
        };
        const onKey = (e) => {
          const step = e.shiftKey ? 10 : 1;
          if (e.key === "ArrowRight" || e.key === "ArrowUp" || e.key === "+") widthPx += step;
          else if (e.key === "ArrowLeft" || e.key === "ArrowDown" || e.key === "-") widthPx -= step;
          else if (e.key === "Enter" || isSpace(e)) {
            e.preventDefault();
            window.removeEventListener("keydown", onKey);
            handle.removeEventListener("pointerdown", onDown);
            handle.removeEventListener("pointermove", onMove);
            handle.removeEventListener("pointerup", onUp);
            area.hidden = true;
            resolve(widthPx / CARD_MM[0]);
            return;
          } else return;
          e.preventDefault();
          show();
        };
        window.addEventListener("keydown", onKey);
        handle.addEventListener("pointerdown", onDown);
        handle.addEventListener("pointermove", onMove);
        handle.addEventListener("pointerup", onUp);
      }),
  );
}

function waitSpace() {
  return new Promise((resolve) => {
    const onKey = (e) => {
      if (e.repeat || !isSpace(e)) return;
      e.preventDefault();
      window.removeEventListener("keydown", onKey);
      resolve(e);
    };
    window.addEventListener("keydown", onKey);
  });
}

/** One blind-spot run: the fixation-to-dot distance in device pixels when Space was pressed
 *  (null when the dot reached the edge first). */
function blindSpotRun(canvas, pxPerMm, repeat) {
  const ctx = fitCanvas(canvas);
  canvas.hidden = false;
  hidePanel();
  const dpr = window.devicePixelRatio || 1;
  const { width: w, height: h } = canvas;
  const cx = w - Math.round(80 * dpr);
  const cy = Math.round(h / 2);
  const radius = Math.max(3, Math.round(1.5 * pxPerMm));
  const speed = config.dotSpeedMmPerS * pxPerMm; // device px per second
  document.body.dataset.repeat = String(repeat);
  document.body.dataset.dotPx = "0";
  setScreen("blindspot");
  return new Promise((resolve) => {
    let t0 = null;
    let dist = 0;
    let done = false;
    const onKey = (e) => {
      if (e.repeat || !isSpace(e)) return;
      e.preventDefault();
      finish(dist);
    };
    const finish = (value) => {
      if (done) return;
      done = true;
      window.removeEventListener("keydown", onKey);
      resolve(value);
    };
    const frame = (ts) => {
      if (done) return;
      if (t0 === null) t0 = ts;
      dist = Math.round(((ts - t0) / 1000) * speed);
      document.body.dataset.dotPx = String(dist);
      if (cx - dist < radius) {
        finish(null);
        return;
      }
      ctx.fillStyle = "#fff";
      ctx.fillRect(0, 0, w, h);
      ctx.fillStyle = "#000";
      const arm = Math.round(10 * dpr);
      ctx.fillRect(cx - arm, cy - dpr, 2 * arm, 2 * dpr);
      ctx.fillRect(cx - dpr, cy - arm, 2 * dpr, 2 * arm);
      ctx.fillStyle = "#d00";
      ctx.beginPath();
      ctx.arc(cx - dist, cy, radius, 0, 2 * Math.PI);
      ctx.fill();
      requestAnimationFrame(frame);
    };
    window.addEventListener("keydown", onKey);
    requestAnimationFrame(frame);
  });
}

/** The blind-spot method: resolves with the viewing distance in millimetres. */
export async function blindSpotMethod(canvas, pxPerMm) {
  message(
    "blindspot-intro",
    "Viewing distance",
    "Sit as you will during the experiment. Close or cover your right eye and look at the black " +
      "cross with your left eye only. A red dot moves away from the cross to the left: press " +
      `Space the moment it disappears. This is done ${BLIND_SPOT_REPEATS} times.`,
    "Press Space to begin.",
  );
  await waitSpace();
  const distances = [];
  while (distances.length < BLIND_SPOT_REPEATS) {
    const px = await blindSpotRun(canvas, pxPerMm, distances.length + 1);
    const mm = px === null ? null : px / pxPerMm;
    if (mm === null || mm < MIN_BLIND_SPOT_MM) {
      message(
        "blindspot-retry",
        "Once more",
        mm === null
          ? "The dot reached the edge. Keep looking at the cross and press Space when the dot disappears."
          : "That was very early. Keep looking at the cross and press Space only when the dot disappears.",
        "Press Space to try again.",
      );
      await waitSpace();
      continue;
    }
    distances.push(mm);
  }
  canvas.hidden = true;
  const meanMm = distances.reduce((a, b) => a + b, 0) / distances.length;
  return meanMm / Math.tan((BLIND_SPOT_DEG * Math.PI) / 180);
}

/** Device pixels per degree of visual angle at the screen centre: the pixels one degree, centred
 *  on the line of sight, spans at distance `distMm`. */
export function pixelsPerDegree(pxPerMm, distMm) {
  return pxPerMm * 2 * distMm * Math.tan((0.5 * Math.PI) / 180);
}
