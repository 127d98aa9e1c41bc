// A small rosbridge v2 client: topics, services and actions over one WebSocket, with
// reconnects (subscriptions and advertisements are replayed on each new connection).

export class Rosbridge extends EventTarget {
  constructor(url) {
    super();
    this.url = url;
    this.ws = null;
    this.connected = false;
    this.counter = 0;
    this.subs = new Map();      // topic -> {type, options, callbacks: Set}
    this.advertised = new Map(); // topic -> type
    this.pending = new Map();   // id -> {resolve, reject, onFeedback}
    this.retry = 500;
    this.closed = false;
    this.connect();
  }

  nextId(op, name) {
    this.counter += 1;
    return `${op}:${name}:${this.counter}`;
  }

  connect() {
    const ws = new WebSocket(this.url);
    this.ws = ws;
    ws.onopen = () => {
      this.connected = true;
      this.retry = 500;
      for (const [topic, sub] of this.subs) this.sendSubscribe(topic, sub);
      for (const [topic, type] of this.advertised) this.send({ op: "advertise", topic, type });
      this.dispatchEvent(new Event("open"));
    };
    ws.onmessage = (event) => this.onMessage(event.data);
    ws.onerror = () => {};
    ws.onclose = () => {
      const was = this.connected;
      this.connected = false;
      for (const [, p] of this.pending) p.reject(new Error("connection lost"));
      this.pending.clear();
      if (was) this.dispatchEvent(new Event("close"));
      if (!this.closed) {
        setTimeout(() => this.connect(), this.retry);
        this.retry = Math.min(this.retry * 2, 5000);
      }
    };
  }

  send(frame) {
    if (this.connected && this.ws.readyState === WebSocket.OPEN) {
      this.ws.send(JSON.stringify(frame));
      return true;
    }
    return false;
  }

  onMessage(text) {
    let frame;
    try {
      frame = JSON.parse(text);
    } catch (err) {
      return;
    }
    switch (frame.op) {
      case "publish": {
        const sub = this.subs.get(frame.topic);
        if (sub) for (const cb of sub.callbacks) cb(frame.msg);
        break;
      }
      case "service_response": {
        const p = this.pending.get(frame.id);
        if (!p) break;
        this.pending.delete(frame.id);
        if (frame.result) p.resolve(frame.values);
        else p.reject(new Error(String(frame.values)));
        break;
      }
      case "action_feedback": {
        const p = this.pending.get(frame.id);
        if (p && p.onFeedback) p.onFeedback(frame.values);
        break;
      }
      case "action_result": {
        const p = this.pending.get(frame.id);
        if (!p) break;
        this.pending.delete(frame.id);
        if (frame.result) p.resolve({ status: frame.status, values: frame.values });
        else p.reject(new Error(String(frame.values)));
        break;
      }
      default:
        break;
    }
  }

  sendSubscribe(topic, sub) {
    this.send({ op: "subscribe", id: `subscribe:${topic}`, topic, type: sub.type, ...sub.options });
  }

  subscribe(topic, type, callback, options = {}) {
    let sub = this.subs.get(topic);
    if (!sub) {
      sub = { type, options, callbacks: new Set() };
      this.subs.set(topic, sub);
      this.sendSubscribe(topic, sub);
    }
    sub.callbacks.add(callback);
    return () => {
      sub.callbacks.delete(callback);
      if (sub.callbacks.size === 0) {
        this.subs.delete(topic);
        this.send({ op: "unsubscribe", id: `subscribe:${topic}`, topic });
      }
    };
  }

  publish(topic, type, msg) {
    if (!this.advertised.has(topic)) {
      this.advertised.set(topic, type);
      this.send({ op: "advertise", topic, type });
    }
    return this.send({ op: "publish", topic, msg });
  }

  callService(service, args = {}, timeout = 10000) {
    return new Promise((resolve, reject) => {
      const id = this.nextId("call_service", service);
      const timer = setTimeout(() => {
        this.pending.delete(id);
        reject(new Error(`${service}: no answer within ${timeout / 1000} s`));
      }, timeout);
      this.pending.set(id, {
        resolve: (v) => { clearTimeout(timer); resolve(v); },
        reject: (e) => { clearTimeout(timer); reject(e); },
      });
      if (!this.send({ op: "call_service", id, service, args })) {
        this.pending.delete(id);
        clearTimeout(timer);
        reject(new Error("not connected"));
      }
    });
  }

  // Returns {id, result: Promise<{status, values}>}.
  sendGoal(action, actionType, goal, onFeedback) {
    const id = this.nextId("send_action_goal", action);
    const result = new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject, onFeedback });
      const sent = this.send({
        op: "send_action_goal", id, action, action_type: actionType, args: goal,
        feedback: Boolean(onFeedback),
      });
      if (!sent) {
        this.pending.delete(id);
        reject(new Error("not connected"));
      }
    });
    return { id, result };
  }

  cancelGoal(action, id) {
    return this.send({ op: "cancel_action_goal", id, action });
  }

  close() {
    this.closed = true;
    if (this.ws) this.ws.close();
  }
}
