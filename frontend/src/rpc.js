// The studio's protocol (docs/studio.md): JSON-RPC 2.0 requests over one WebSocket, and
// the server's notifications to handlers registered with `on`.
export class Rpc {
  constructor(url) {
    this.url = url;
    this.next = 1;
    this.waiting = new Map();
    this.handlers = new Map();
  }

  open() {
    return new Promise((resolve, reject) => {
      const ws = new WebSocket(this.url);
      this.ws = ws;
      ws.onopen = () => resolve(this);
      ws.onerror = () => reject(new Error("the studio's server refused the connection"));
      ws.onclose = () => this.emit("closed", {});
      ws.onmessage = (event) => this.receive(JSON.parse(event.data));
    });
  }

  receive(message) {
    if (message.id !== undefined && this.waiting.has(message.id)) {
      const { resolve, reject } = this.waiting.get(message.id);
      this.waiting.delete(message.id);
      if (message.error) reject(new Error(message.error.message));
      else resolve(message.result);
      return;
    }
    if (message.method) this.emit(message.method, message.params || {});
  }

  emit(method, params) {
    for (const fn of this.handlers.get(method) || []) fn(params);
  }

  on(method, fn) {
    if (!this.handlers.has(method)) this.handlers.set(method, []);
    this.handlers.get(method).push(fn);
  }

  call(method, params = {}) {
    const id = this.next++;
    return new Promise((resolve, reject) => {
      this.waiting.set(id, { resolve, reject });
      this.ws.send(JSON.stringify({ jsonrpc: "2.0", id, method, params }));
    });
  }
}
