// Encoded videos (frame packs: a video's frames as lossless WebP files back to back), fetched
// once per session and kept within a byte budget: in Cache Storage (on disk) where the page is
// a secure context, else in memory (at most MEMORY_CAP). Least recently used videos go first,
// never one of the current or the next trials'. Videos the next trials need are fetched in the
// background, one at a time, in the order they are needed.

import { sleep } from "./ui.js";

const MEMORY_CAP = 768e6;
const EXT = "webpframes";
const FIRST_DELAY_MS = 250;
const MAX_DELAY_MS = 8000;

/** A fetched video: its bytes (a Blob) and each frame's byte range in them. */
export class Pack {
  constructor(blob, ranges) {
    this.blob = blob;
    this.ranges = ranges;
  }

  /** Frame `n`'s WebP file. */
  frame(n) {
    const [a, b] = this.ranges[n];
    return this.blob.slice(a, b, "image/webp");
  }
}

/** The frames' byte ranges, from the RIFF headers (`RIFF`, little-endian size, `WEBP`). */
async function frameRanges(blob) {
  const ranges = [];
  let at = 0;
  while (at < blob.size) {
    const head = new DataView(await blob.slice(at, at + 12).arrayBuffer());
    const tag = (o) => String.fromCharCode(...[0, 1, 2, 3].map((k) => head.getUint8(o + k)));
    if (head.byteLength < 12 || tag(0) !== "RIFF" || tag(8) !== "WEBP") {
      throw new Error(`a video is damaged at byte ${at}`);
    }
    const size = head.getUint32(4, true);
    const end = at + 8 + size + (size & 1);
    if (end > blob.size) throw new Error("a video is cut short");
    ranges.push([at, end]);
    at = end;
  }
  return ranges;
}

export class VideoStore {
  /** `base`: the server's video route or the static server's folder; `settings`: State.client. */
  constructor(api, settings, frames) {
    this.api = api;
    this.settings = settings;
    this.frames = frames;
    this.entries = new Map(); // id -> {bytes, used, pack: Promise<Pack>}
    this.queue = [];
    this.pinned = new Set();
    this.pumping = false;
    this.fetchedBytes = 0;
    this.fetches = 0;
    this.cache = null;
    this.budget = Math.min(settings.cache_bytes, MEMORY_CAP);
    this.cacheName = `blurlab-videos-${api.token}`;
  }

  /** Open Cache Storage if the page may use it; keep what an earlier load of the page fetched. */
  async open() {
    try {
      if (!window.isSecureContext || !window.caches) return;
      this.cache = await caches.open(this.cacheName);
      this.budget = this.settings.cache_bytes;
      for (const req of await this.cache.keys()) {
        const id = req.url.split("/").pop().replace(`.${EXT}`, "");
        const res = await this.cache.match(req);
        const blob = await res.blob();
        this.entries.set(id, { bytes: blob.size, used: 0, pack: this.parse(blob) });
      }
    } catch (_) {
      this.cache = null;
      this.budget = Math.min(this.settings.cache_bytes, MEMORY_CAP);
    }
  }

  url(id) {
    const base = this.settings.video_base;
    return base ? `${base}/${id}.${EXT}` : `${this.api.base}/video/${id}`;
  }

  /** Keep these videos (the current and next trials') from eviction. */
  pin(ids) {
    this.pinned = new Set(ids);
  }

  /** Fetch these videos in the background, in this order, after any already asked for. */
  want(ids) {
    for (const id of ids) {
      if (!this.entries.has(id) && !this.queue.includes(id)) this.queue.push(id);
    }
    this.pump();
  }

  async pump() {
    if (this.pumping) return;
    this.pumping = true;
    try {
      while (this.queue.length > 0) {
        const id = this.queue.shift();
        if (this.entries.has(id)) continue;
        await this.get(id).catch(() => {});
      }
    } finally {
      this.pumping = false;
    }
  }

  /** The video `id`, fetched now if it is not kept. */
  get(id) {
    let e = this.entries.get(id);
    if (!e) {
      e = { bytes: 0, used: 0, pack: null };
      e.pack = this.fetchPack(id, e);
      this.entries.set(id, e);
      e.pack.catch(() => this.entries.delete(id));
    }
    e.used = performance.now();
    return e.pack;
  }

  async fetchPack(id, entry) {
    const url = this.url(id);
    const res = await fetchRetrying(url);
    let blob;
    if (this.cache) {
      await this.cache.put(url, res);
      blob = await (await this.cache.match(url)).blob();
    } else {
      blob = await res.blob();
    }
    entry.bytes = blob.size;
    this.fetchedBytes += blob.size;
    this.fetches += 1;
    const pack = await this.parse(blob);
    this.evict();
    return pack;
  }

  async parse(blob) {
    const ranges = await frameRanges(blob);
    if (ranges.length !== this.frames) {
      throw new Error(`a video has ${ranges.length} frames, not ${this.frames}`);
    }
    return new Pack(blob, ranges);
  }

  /** Drop the least recently used videos until the kept bytes fit the budget. */
  evict() {
    let total = 0;
    for (const e of this.entries.values()) total += e.bytes;
    const old = [...this.entries].filter(([id]) => !this.pinned.has(id));
    old.sort((a, b) => a[1].used - b[1].used);
    for (const [id, e] of old) {
      if (total <= this.budget) break;
      total -= e.bytes;
      this.entries.delete(id);
      if (this.cache) this.cache.delete(this.url(id)).catch(() => {});
    }
  }

  /** The session is over: free the disk. */
  async clear() {
    this.entries.clear();
    if (this.cache) await caches.delete(this.cacheName).catch(() => {});
  }
}

/** GET with retries on network errors, 5xx and 429 (as api.js), failing on other errors. */
async function fetchRetrying(url) {
  for (let attempt = 0; ; attempt++) {
    let res = null;
    try {
      res = await fetch(url, { cache: "no-store", credentials: "omit" });
    } catch (_) {
      res = null;
    }
    if (res && res.ok) return res;
    if (res && res.status < 500 && res.status !== 429) {
      throw new Error(`HTTP ${res.status} for a video`);
    }
    await sleep(Math.min(MAX_DELAY_MS, FIRST_DELAY_MS * 2 ** attempt) * (0.75 + 0.5 * Math.random()));
  }
}
