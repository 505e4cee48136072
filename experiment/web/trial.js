// One trial: its videos (encoded, from the VideoStore), decoded while they play, a lookahead of
// frames ahead of the one shown (State.client.lookahead_frames); then the presentation paced by
// requestAnimationFrame (the lab app's presentation.rs, step for step):
//
//   sequential: fixation -> pair 1 (loops x video) -> gap -> pair 2 (loops x video) -> respond
//   grid:       fixation -> both pairs at once (loops x video)                      -> respond
//
// The frame shown is floor((t - t0) fps) with t the rAF timestamp and t0 the timestamp of the
// pair's first frame: frames follow the clock, so a frame not decoded in time, like a missed
// refresh, is skipped (counted as dropped) instead of slowing the video. A frame drawn later than
// the first refresh at or after its due time is counted as late. A pair starts only once its
// first frames are decoded (before the trial for pair 1, during the gap for pair 2).

import { drawBlank, drawFixation, fitCanvas, videoRects, windowDevicePx } from "./canvas.js";

// rAF timestamps of a refresh that falls exactly on a frame's due time may come a hair early.
const DUE_TOLERANCE_MS = 0.5;

const BITMAP_OPTIONS = { colorSpaceConversion: "none", premultiplyAlpha: "none" };

/** Decode frame `n` of a pack (exact: no colour conversion, no premultiplication). */
export function decodeFrame(pack, n) {
  return createImageBitmap(pack.frame(n), BITMAP_OPTIONS);
}

/**
 * One video's frames decoded ahead of playback: frame g (over the loops; frame g % frames of the
 * video) is asked for once frame g - ahead is shown, and closed once a later one is.
 */
export class Lookahead {
  constructor(pack, frames, loops, ahead) {
    this.pack = pack;
    this.frames = frames;
    this.total = frames * loops;
    this.ahead = ahead;
    this.bitmaps = new Map();
    this.pending = new Map();
    this.next = 0;
    this.closed = false;
    this.error = null;
  }

  /** Ask for the frames up to `shown + ahead`. */
  fill(shown) {
    const end = Math.min(this.total, shown + this.ahead + 1);
    for (; this.next < end; this.next++) {
      const g = this.next;
      const p = decodeFrame(this.pack, g % this.frames).then(
        (b) => {
          if (this.closed) b.close();
          else this.bitmaps.set(g, b);
        },
        (e) => {
          this.error = e;
        },
      );
      this.pending.set(g, p);
      p.finally(() => this.pending.delete(g));
    }
  }

  /** Ask for the lookahead's frames and wait for the first third of them (at least one): the
   *  rest decode while the video plays. */
  async prime() {
    this.fill(0);
    const first = Math.max(1, Math.ceil(this.ahead / 3));
    await Promise.all([...this.pending].filter(([g]) => g < first).map(([, p]) => p));
    if (this.error) throw this.error;
  }

  get(g) {
    return this.bitmaps.get(g);
  }

  /** Frame g is on screen: close the frames before it, ask for the next ones. */
  shown(g) {
    for (const [k, b] of this.bitmaps) {
      if (k < g) {
        b.close();
        this.bitmaps.delete(k);
      }
    }
    this.fill(g);
  }

  close() {
    this.closed = true;
    for (const b of this.bitmaps.values()) b.close();
    this.bitmaps.clear();
  }
}

/**
 * Decoders for the given pairs (indices 0/1) of a trial: `decoders[p][s]`, one Lookahead per
 * distinct video (a pair showing one video twice decodes it once). `packs` maps id -> Pack.
 */
export function decoders(state, packs, pairs) {
  const out = [null, null];
  const { frames } = state.video;
  const ahead = state.client.lookahead_frames;
  for (const p of pairs) {
    const ids = state.trial.pairs[p];
    const first = new Lookahead(packs.get(ids[0]), frames, state.playback.loops, ahead);
    const second =
      ids[1] === ids[0] ? first : new Lookahead(packs.get(ids[1]), frames, state.playback.loops, ahead);
    out[p] = [first, second];
  }
  return out;
}

function distinct(decs) {
  return [...new Set(decs.flat().filter(Boolean))];
}

/** Prime the decoders of some pairs; returns when their first frames are decoded. */
export function prime(decs) {
  return Promise.all(distinct(decs).map((d) => d.prime()));
}

export function closeAll(decs) {
  for (const d of distinct(decs)) d.close();
}

function median(xs) {
  if (xs.length === 0) return null;
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.floor(s.length / 2)];
}

/** Draw the given pairs' videos (pairs: indices 0/1) over the background; `pick(p, s)` gives
 *  the bitmap of pair p's side s. */
export function drawPairs(ctx, state, pick, pairs) {
  const rects = videoRects([ctx.canvas.width, ctx.canvas.height], state.video, state.playback);
  drawBlank(ctx, state.playback.background);
  for (const p of pairs) {
    for (let s = 0; s < 2; s++) {
      const r = rects[p][s];
      ctx.drawImage(pick(p, s), r.x, r.y, r.w, r.h);
    }
  }
  return rects;
}

/**
 * Play the trial on `canvas`; resolves when the answer is due with the timing record:
 * `{respondAt, onsets_ms, frame_times_ms, dropped_frames, late_frames, refresh_interval_ms}`.
 * `packs` maps video id -> Pack; `firstDecs` holds the primed decoders of the first pairs shown.
 * `refreshMs` is the refresh interval measured before (used until this trial measures its own).
 */
export function play(canvas, state, packs, firstDecs, refreshMs) {
  const pb = state.playback;
  const fps = state.video.fps;
  const total = state.video.frames * pb.loops;
  const steps =
    pb.layout === "sequential"
      ? [
          { kind: "fixation", ms: pb.fixation_ms },
          { kind: "play", pairs: [0] },
          { kind: "gap", ms: pb.gap_ms, next: [1] },
          { kind: "play", pairs: [1] },
          { kind: "respond" },
        ]
      : [{ kind: "fixation", ms: pb.fixation_ms }, { kind: "play", pairs: [0, 1] }, { kind: "respond" }];
  const ctx = fitCanvas(canvas);
  canvas.hidden = false;
  let decs = firstDecs;
  let nextDecs = null;
  let nextReady = false;
  let current = 0;
  let start = null;
  let last = null;
  let prev = null;
  const deltas = [];
  const onsets = [];
  const times = [];
  let dropped = 0;
  let late = 0;
  return new Promise((resolve, reject) => {
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
          if (first && step.next) {
            // Decode the next pair's first frames during the gap.
            nextDecs = decoders(state, packs, step.next);
            nextReady = false;
            prime(nextDecs).then(() => (nextReady = true), reject);
          }
          if (elapsed >= step.ms && (!step.next || nextReady)) {
            if (step.next) decs = nextDecs;
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
          closeAll(decs);
          current += 1;
          start = null;
          continue;
        }
        if (index !== last) {
          const ready = step.pairs.every((p) => decs[p].every((d) => d.get(index)));
          if (ready) {
            dropped += index - (last === null ? 0 : last + 1);
            const due = start + (index * 1000) / fps;
            if (refresh && ts - due >= refresh + DUE_TOLERANCE_MS) late += 1;
            drawPairs(ctx, state, (p, s) => decs[p][s].get(index), step.pairs);
            times.push(ts);
            last = index;
          }
          // A frame not decoded in time is skipped (dropped) once a later one is drawn.
          for (const d of new Set(step.pairs.flatMap((p) => decs[p]))) d.shown(index);
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
