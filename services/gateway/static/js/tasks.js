// The task list: tasks/get once, then live from tasks/status; start, pause, resume, stop.

export class TaskPanel {
  constructor(ros, service, list, empty, onError) {
    this.ros = ros;
    this.service = service; // name -> the tasks/<name> service
    this.list = list;
    this.empty = empty;
    this.onError = onError;
    this.tasks = new Map();
  }

  async call(name, id = "", body = "") {
    const res = await this.ros.callService(this.service(name), { id, body });
    if (!res.success) throw new Error(res.message || `tasks/${name} failed (${res.code})`);
    return res.body ? JSON.parse(res.body) : null;
  }

  async refresh() {
    try {
      const list = await this.call("get");
      this.tasks = new Map((Array.isArray(list) ? list : []).map((t) => [t.id, t]));
    } catch (err) {
      this.tasks = new Map();
    }
    this.render();
  }

  onStatus(m) {
    if (m.event === "deleted") {
      this.tasks.delete(m.id);
      this.render();
      return;
    }
    let doc = null;
    try {
      doc = m.task ? JSON.parse(m.task) : null;
    } catch (err) {
      doc = null;
    }
    const prev = this.tasks.get(m.id) || {};
    this.tasks.set(m.id, { ...prev, ...(doc || {}), id: m.id, name: m.name || prev.name,
                           state: m.state, progress: m.progress });
    this.render();
  }

  render() {
    const list = this.list;
    list.replaceChildren();
    this.empty.hidden = this.tasks.size > 0;
    for (const t of this.tasks.values()) {
      const li = document.createElement("li");
      li.dataset.id = t.id;
      li.dataset.state = t.state;
      const head = document.createElement("div");
      head.className = "row";
      const title = document.createElement("span");
      title.className = "name";
      title.textContent = t.name || t.id;
      title.title = t.name || t.id;
      const badge = document.createElement("span");
      badge.className = `badge ${t.state}`;
      badge.textContent = t.state;
      head.append(title, badge);
      const foot = document.createElement("div");
      foot.className = "row";
      const bar = document.createElement("div");
      bar.className = "progress";
      const fill = document.createElement("span");
      const p = t.progress || 0;
      fill.style.width = `${Math.round(Math.max(0, Math.min(1, p > 1 ? p / 100 : p)) * 100)}%`;
      bar.append(fill);
      foot.append(bar);
      const buttons = t.state === "WORKING" ? [["pause", "Pause"], ["stop", "Stop"]]
        : t.state === "PAUSED" ? [["resume", "Resume"], ["stop", "Stop"]]
        : [["start", "Start"]];
      for (const [call, label] of buttons) {
        const b = document.createElement("button");
        b.type = "button";
        b.textContent = label;
        b.dataset.call = call;
        b.addEventListener("click", () => this.call(call, t.id)
          .then((doc) => { if (doc && doc.id) this.onStatus({ ...doc, task: JSON.stringify(doc) }); })
          .catch((err) => this.onError(err.message)));
        foot.append(b);
      }
      li.classList.add("task");
      li.append(head, foot);
      list.append(li);
    }
  }
}
