// The native API as the console uses it: JSON requests with the API's own errors, and the
// WebSocket of status and events, reconnected when it drops. Same origin: the session cookie
// (set by POST /api/login) goes with every request and with the WebSocket's handshake.

export class ApiError extends Error {
  constructor(status, code, message) {
    super(message);
    this.status = status;
    this.code = code;
  }
}

export class Api {
  constructor(base = "") {
    this.base = base;
    this.onUnauthorized = null; // called on any 401: the console shows its login form
  }

  async request(method, path, body) {
    const init = { method, headers: {}, credentials: "same-origin" };
    if (body !== undefined) {
      init.headers["Content-Type"] = "application/json";
      init.body = JSON.stringify(body);
    }
    let answer;
    try {
      answer = await fetch(this.base + path, init);
    } catch (err) {
      throw new ApiError(0, "unreachable", `the robot does not answer (${err.message})`);
    }
    if (answer.status === 204) return null;
    const type = answer.headers.get("content-type") || "";
    const data = type.includes("json") ? await answer.json() : await answer.text();
    if (!answer.ok) {
      const error = data && data.error ? data.error : { code: "http_" + answer.status,
        message: String(data).slice(0, 200) };
      if (answer.status === 401 && this.onUnauthorized) this.onUnauthorized();
      throw new ApiError(answer.status, error.code, error.message);
    }
    return data;
  }

  get(path) { return this.request("GET", path); }
  post(path, body) { return this.request("POST", path, body === undefined ? {} : body); }
  postEmpty(path) { return this.request("POST", path); }
  put(path, body) { return this.request("PUT", path, body); }
  del(path) { return this.request("DELETE", path); }
}

// The WebSocket of GET /api/ws: status at `rate` per simulated second, events, the live map
// while mapping. Reconnects after a drop (a slow client is closed with 1008 by the server),
// waiting longer each time up to 5 s.
export class Stream {
  constructor(rate, onMessage, onState) {
    this.rate = rate;
    this.onMessage = onMessage;
    this.onState = onState;
    this.delay = 250;
    this.stopped = false;
    this.socket = null;
  }

  open() {
    const scheme = location.protocol === "https:" ? "wss:" : "ws:";
    const socket = new WebSocket(`${scheme}//${location.host}/api/ws?rate=${this.rate}`);
    this.socket = socket;
    socket.onopen = () => { this.delay = 250; this.onState("connected"); };
    socket.onmessage = (m) => {
      try {
        this.onMessage(JSON.parse(m.data));
      } catch (err) {
        console.error("bad stream message", err);
      }
    };
    socket.onclose = (e) => {
      this.socket = null;
      if (this.stopped) return;
      if (this.switching) { this.switching = false; this.open(); return; }
      this.onState(`disconnected (${e.code}${e.reason ? ": " + e.reason : ""}), retrying`);
      setTimeout(() => this.open(), this.delay);
      this.delay = Math.min(this.delay * 2, 5000);
    };
  }

  // Reopen at another rate (the server's rate is per simulated second).
  setRate(rate) {
    this.rate = rate;
    this.switching = true;
    if (this.socket) this.socket.close();
  }

  close() {
    this.stopped = true;
    if (this.socket) this.socket.close();
  }
}
