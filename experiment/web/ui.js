// Screens and keys. Every screen change sets body[data-screen] and bumps body[data-seq], which is
// what a WebDriver test waits on; nothing there tells the level or which pair differs.

const $ = (id) => document.getElementById(id);
let seq = 0;

/** Name the current screen for tests and for styling. */
export function setScreen(name) {
  seq += 1;
  document.body.dataset.screen = name;
  document.body.dataset.seq = String(seq);
}

/** A text screen: title, body, hint (what to press). */
export function message(name, title, text, hint = "") {
  $("canvas").hidden = true;
  $("card-area").hidden = true;
  const panel = $("panel");
  panel.hidden = false;
  $("title").textContent = title;
  $("text").textContent = text;
  $("hint").textContent = hint;
  setScreen(name);
}

/** Hide the panel (the canvas or the card takes the screen). */
export function hidePanel() {
  $("panel").hidden = true;
}

/** The key of a KeyboardEvent as the design names keys (KeyboardEvent.key; Space is " "). */
export function isSpace(e) {
  return e.key === " " || e.code === "Space";
}

/**
 * The next keydown whose key is in `keys` (KeyboardEvent.key values; " " for Space), ignoring
 * auto-repeat. Resolves with the event.
 */
export function nextKey(keys) {
  return new Promise((resolve) => {
    const onKey = (e) => {
      if (e.repeat || !keys.includes(e.key)) return;
      e.preventDefault();
      window.removeEventListener("keydown", onKey);
      resolve(e);
    };
    window.addEventListener("keydown", onKey);
  });
}

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
