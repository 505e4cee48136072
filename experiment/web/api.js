// The session API (docs/web.md, "HTTP API"). Network failures, 5xx and 429 are retried with
// exponential back-off until the server answers, so a dropped connection or a restarted server
// loses nothing; 4xx answers are errors the caller shows.

import { sleep } from "./ui.js";

/** An error answer of the server: its status and its message. */
export class ApiError extends Error {
  constructor(status, message) {
    super(message);
    this.status = status;
  }
}

const FIRST_DELAY_MS = 250;
const MAX_DELAY_MS = 8000;

export class Api {
  /** `onRetry(attempt, delayMs)` is told about each retry (the page shows it). */
  constructor(token, tab, onRetry = () => {}) {
    this.base = `/api/s/${encodeURIComponent(token)}`;
    this.token = token;
    this.tab = tab;
    this.onRetry = onRetry;
  }

  /** One request, retried until the server gives a non-5xx, non-429 answer. */
  async request(method, path, body) {
    for (let attempt = 0; ; attempt++) {
      let res = null;
      try {
        res = await fetch(this.base + path, {
          method,
          cache: "no-store",
          headers: body === undefined ? {} : { "Content-Type": "application/json" },
          body: body === undefined ? undefined : JSON.stringify(body),
        });
      } catch (_) {
        res = null; // network error: retry
      }
      if (res && res.status < 500 && res.status !== 429) {
        const json = await res.json().catch(() => ({}));
        if (!res.ok) throw new ApiError(res.status, json.error || `HTTP ${res.status}`);
        return json;
      }
      const delay = Math.min(MAX_DELAY_MS, FIRST_DELAY_MS * 2 ** attempt);
      this.onRetry(attempt + 1, delay);
      await sleep(delay * (0.75 + 0.5 * Math.random()));
    }
  }

  claim() {
    return this.request("POST", "/claim", { tab: this.tab });
  }

  state() {
    return this.request("GET", `/state?tab=${encodeURIComponent(this.tab)}`);
  }

  display(facts) {
    return this.request("POST", "/display", { tab: this.tab, ...facts });
  }

  /** The participant's answer to the consent text. */
  consent(accept) {
    return this.request("POST", "/consent", { tab: this.tab, accept });
  }

  /** Leave before any trial: `window_too_small` or `browser_unsupported`. */
  screenOut(reason) {
    return this.request("POST", "/screen_out", { tab: this.tab, reason });
  }

  advance(from) {
    return this.request("POST", "/advance", { tab: this.tab, from });
  }

  /** Post an answer until it is acknowledged: `{ack, feedback, state}`. */
  answer(answer) {
    return this.request("POST", "/answer", { tab: this.tab, ...answer });
  }
}
