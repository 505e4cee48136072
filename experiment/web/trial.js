// One trial: preload every frame of its four videos into decoded ImageBitmaps, then play the
// presentation paced by requestAnimationFrame (the lab app's presentation.rs, step for step):
//
//   sequential: fixation -> pair 1 (loops x video) -> gap -> pair 2 (loops x video) -> respond
//   grid:       fixation -> both pairs at once (loops x video)                      -> respond
//
// The frame shown is floor((t - t0) fps) with t the rAF timestamp and t0 the timestamp of the
// pair's first frame: frames follow the clock, so a missed refresh skips a frame (counted as
// dropped) instead of slowing the video. A frame drawn later than the first refresh at or after
// its due time is counted as late.

import { drawBlank, drawFixation, fitCanvas, videoRects, windowDevicePx } from "./stage.js";

const PRELOAD_CONCURRENCY = 6;
// rAF timestamps of a refresh that falls exactly on a frame's due time may come a hair early.
const DUE_TOLERANCE_MS = 0.5;

const BITMAP_OPTIONS = { colorSpaceConversion: "none", premultiplyAlpha: "none" };

/** Fetch one frame, retrying network errors a few times; returns [ImageBitmap, bytes]. */
async function loadFrame(url) {
  for (let attempt = 0; ; attempt++) {
    try {
      const res = await fetch(url, { cache: "no-store" });
      if (!res.ok) throw new Error(`HTTP ${res.status} for a frame`);
      const blob = await res.blob();
      return [await createImageBitmap(blob, BITMAP_OPTIONS), blob.size];
    } catch (e) {
      if (attempt >= 4) throw e;
      await new Promise((r) => setTimeout(r, 250 * 2 ** attempt));
    }
  }
}

/**
 * Every frame of the trial's four videos, decoded: `{frames: [[pair1 left, pair1 right],
 * [pair2 left, pair2 right]] (arrays of ImageBitmap), bytes, ms}`.
 */
export async function preload(api, trial, video) {
  const t0 = performance.now();
  const jobs = [];
  const frames = trial.pairs.map((pair) => pair.map(() => new Array(video.frames)));
  trial.pairs.forEach((pair, p) =>
    pair.forEach((handle, s) => {
      for (let n = 0; n < video.frames; n++) jobs.push({ p, s, n, url: api.frameUrl(handle, n) });
    }),
  );
  let next = 0;
  let bytes = 0;
  const worker = async () => {
    while (next < jobs.length) {
      const job = jobs[next++];
      const [bitmap, size] = await loadFrame(job.url);
      frames[job.p][job.s][job.n] = bitmap;
      bytes += size;
    }
  };
  try {
    await Promise.all(Array.from({ length: PRELOAD_CONCURRENCY }, worker));
  } catch (e) {
    release(frames);
    throw e;
  }
  return { frames, bytes, ms: performance.now() - t0 };
}

/** Free the decoded frames of a finished trial. */
export function release(frames) {
  for (const pair of frames) for (const video of pair) for (const b of video) if (b) b.close();
}

function median(xs) {
  if (xs.length === 0) return null;
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.floor(s.length / 2)];
}

/** Draw frame `n` of the given pairs' videos (pairs: indices 0/1) over the background. */
export function drawPairs(ctx, state, frames, pairs, n) {
  const rects = videoRects([ctx.canvas.width, ctx.canvas.height], state.video, state.playback);
  drawBlank(ctx, state.playback.background);
  for (const p of pairs) {
    for (let s = 0; s < 2; s++) {
      const r = rects[p][s];
      ctx.drawImage(frames[p][s][n], r.x, r.y, r.w, r.h);
    }
  }
  return rects;
}

/**
 * Play the trial on `canvas`; resolves when the answer is due with the timing record:
 * `{respondAt, onsets_ms, frame_times_ms, dropped_frames, late_frames, refresh_interval_ms}`.
 * `refreshMs` is the refresh interval measured before (used until this trial measures its own).
 */
export function play(canvas, state, frames, refreshMs) {
  const pb = state.playback;
  const fps = state.video.fps;
  const total = state.video.frames * pb.loops;
  const steps =
    pb.layout === "sequential"
      ? [
          { kind: "fixation", ms: pb.fixation_ms },
          { kind: "play", pairs: [0] },
          { kind: "gap", ms: pb.gap_ms },
          { kind: "play", pairs: [1] },
          { kind: "respond" },
        ]
      : [{ kind: "fixation", ms: pb.fixation_ms }, { kind: "play", pairs: [0, 1] }, { kind: "respond" }];
  const ctx = fitCanvas(canvas);
  canvas.hidden = false;
  let current = 0;
  let start = null;
  let last = null;
  let prev = null;
  const deltas = [];
  const onsets = [];
  const times = [];
  let dropped = 0;
  let late = 0;
  return new Promise((resolve) => {
    const tick = (ts) => {
      if (prev !== null) deltas.push(ts - prev);
      prev = ts;
      const refresh = deltas.length >= 10 ? median(deltas) : refreshMs;
      for (;;) {
        const step = steps[current];
        const first = start === null;
        if (first) start = ts;
        const elapsed = ts - start;
        if (step.kind === "fixation" || step.kind === "gap") {
          if (elapsed >= step.ms) {
            current += 1;
            start = null;
            continue;
          }
          if (first) {
            if (step.kind === "fixation") drawFixation(ctx, pb.background);
            else drawBlank(ctx, pb.background);
          }
          requestAnimationFrame(tick);
          return;
        }
        if (step.kind === "respond") {
          drawBlank(ctx, pb.background);
          resolve({
            respondAt: ts,
            onsets_ms: onsets,
            frame_times_ms: times,
            dropped_frames: dropped,
            late_frames: late,
            refresh_interval_ms: refresh,
          });
          return;
        }
        if (first) {
          onsets.push(ts);
          last = null;
        }
        const index = Math.floor(((elapsed + DUE_TOLERANCE_MS) * fps) / 1000);
        if (index >= total) {
          // Frames due before the end but never drawn were dropped too.
          dropped += total - (last === null ? 0 : last + 1);
          current += 1;
          start = null;
          continue;
        }
        if (index !== last) {
          dropped += index - (last === null ? 0 : last + 1);
          const due = start + (index * 1000) / fps;
          if (refresh && ts - due >= refresh + DUE_TOLERANCE_MS) late += 1;
          drawPairs(ctx, state, frames, step.pairs, index % state.video.frames);
          times.push(ts);
          last = index;
        }
        requestAnimationFrame(tick);
        return;
      }
    };
    requestAnimationFrame(tick);
  });
}

/** Whether the window holds the trial at 1:1 device pixels; else the message to show. */
export function tooSmall(state) {
  const [w, h] = windowDevicePx();
  const [nw, nh] = state.min_window_px;
  if (w >= nw && h >= nh) return null;
  return (
    `The videos are shown pixel for pixel and need a window of at least ${nw} x ${nh} device ` +
    `pixels; this window has ${w} x ${h}. Enlarge the window (or use full screen or a larger ` +
    `screen); the session goes on by itself when it fits.`
  );
}
