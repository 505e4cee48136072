// The trial canvas at 1:1 device pixels and where the videos go on it (the same rule as the lab
// app's layout.rs: the two videos of a pair side by side, `spacing` apart, centred, whole pixels).

/** The window's size in device pixels. */
export function windowDevicePx() {
  const dpr = window.devicePixelRatio || 1;
  return [Math.round(window.innerWidth * dpr), Math.round(window.innerHeight * dpr)];
}

/**
 * Size the canvas to the window in device pixels and its CSS box to (device px / dpr), so one
 * canvas pixel is one device pixel; smoothing off. Returns the 2D context.
 */
export function fitCanvas(canvas) {
  const dpr = window.devicePixelRatio || 1;
  const [w, h] = windowDevicePx();
  if (canvas.width !== w) canvas.width = w;
  if (canvas.height !== h) canvas.height = h;
  canvas.style.width = `${w / dpr}px`;
  canvas.style.height = `${h / dpr}px`;
  const ctx = canvas.getContext("2d", { alpha: false });
  // Resizing a canvas resets its context state.
  ctx.imageSmoothingEnabled = false;
  return ctx;
}

/** Device pixels a trial needs: [w, h]. */
export function neededPx(video, playback) {
  const w = 2 * video.width + playback.spacing_px;
  const h = playback.layout === "sequential" ? video.height : 2 * video.height + playback.spacing_px;
  return [w, h];
}

/** `rects[pair][side]` = {x, y, w, h} in whole device pixels on a `screen` [w, h]. */
export function videoRects(screen, video, playback) {
  const [needW, needH] = neededPx(video, playback);
  const x0 = Math.floor((screen[0] - needW) / 2);
  const y0 = Math.floor((screen[1] - needH) / 2);
  const { width: vw, height: vh } = video;
  const row = (y) => [
    { x: x0, y, w: vw, h: vh },
    { x: x0 + vw + playback.spacing_px, y, w: vw, h: vh },
  ];
  const second = playback.layout === "sequential" ? y0 : y0 + vh + playback.spacing_px;
  return [row(y0), row(second)];
}

export function cssColor(rgb) {
  return `rgb(${rgb[0]}, ${rgb[1]}, ${rgb[2]})`;
}

/** A fixation cross at the centre, in whole device pixels. */
export function drawFixation(ctx, background) {
  const { width: w, height: h } = ctx.canvas;
  ctx.fillStyle = cssColor(background);
  ctx.fillRect(0, 0, w, h);
  const lum = (background[0] + background[1] + background[2]) / 3;
  ctx.fillStyle = lum > 128 ? "#000" : "#fff";
  const dpr = window.devicePixelRatio || 1;
  const arm = Math.round(12 * dpr);
  const thick = Math.max(1, Math.round(2 * dpr));
  const cx = Math.floor(w / 2);
  const cy = Math.floor(h / 2);
  ctx.fillRect(cx - arm, cy - Math.floor(thick / 2), 2 * arm, thick);
  ctx.fillRect(cx - Math.floor(thick / 2), cy - arm, thick, 2 * arm);
}

export function drawBlank(ctx, background) {
  ctx.fillStyle = cssColor(background);
  ctx.fillRect(0, 0, ctx.canvas.width, ctx.canvas.height);
}
