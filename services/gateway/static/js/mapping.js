// The mapping card: start (driven by hand, or exploring by itself), stop and save the map the
// mapping node builds (slam/start, slam/stop, slam/save, the explore action), its state live
// from slam/state, the robot's track from slam/track. The growing map itself comes on `map`,
// which the map view draws already; the teleop pad drives while mapping.

const NAME = /^[A-Za-z0-9_][A-Za-z0-9_.-]{0,63}$/;

export class MappingPanel {
  constructor(ros, name, view, els, toast) {
    this.ros = ros;
    this.name = name; // rel -> the robot's topic or service name
    this.view = view;
    this.els = els; // {state, detail, start, explore, stop, save, saveName}
    this.toast = toast;
    this.state = { state: "idle" };
    this.exploreGoal = null; // the page's explore goal id
    this.exploreText = "";
    this.onPose = null; // (pose) while mapping: slam/pose, the robot in the map being built
    els.start.addEventListener("click", () => this.start("laser"));
    els.explore.addEventListener("click", () => this.start("explore"));
    els.stop.addEventListener("click", () => this.stop());
    els.save.addEventListener("click", () => this.save());
    els.saveName.addEventListener("keydown", (e) => { if (e.key === "Enter") this.save(); });
    this.render();
  }

  subscribe() {
    const ros = this.ros;
    ros.subscribe(this.name("slam/state"), "zenros_msgs/MappingState", (m) => {
      this.state = m;
      if (m.state === "idle") this.view.setTrack([]);
      this.render();
    });
    ros.subscribe(this.name("slam/track"), "nav_msgs/Path", (m) => {
      if (this.mapping()) {
        this.view.setTrack(m.poses.map((p) => ({ x: p.pose.position.x, y: p.pose.position.y })));
      }
    }, { throttle_rate: 500, queue_length: 1 });
    ros.subscribe(this.name("slam/pose"), "geometry_msgs/PoseWithCovarianceStamped", (m) => {
      if (this.mapping() && this.onPose) this.onPose(m.pose.pose);
    }, { throttle_rate: 50, queue_length: 1 });
  }

  mapping() {
    return this.state.state === "mapping" || this.state.state === "starting";
  }

  // slam/* answer `code` (a ResultCode, 0 OK) and `message`.
  async call(service, args) {
    const res = await this.ros.callService(this.name(service), args, 30000);
    if (res.code !== 0) throw new Error(res.message || `${service} failed (code ${res.code})`);
    return res;
  }

  async start(mode) {
    this.setBusy(true);
    try {
      await this.call("slam/start", { mode, map_name: "", use_initial_pose: false });
      this.toast(mode === "explore" ? "mapping: exploring by itself" : "mapping: drive the robot");
      if (mode === "explore") this.explore();
    } catch (err) {
      this.toast(`cannot start mapping: ${err.message}`, true);
    } finally {
      this.setBusy(false);
    }
  }

  explore() {
    const { id, result } = this.ros.sendGoal(this.name("explore"), "zenros_msgs/Explore", {
      return_to_start: true, min_frontier_size: 0.5, progress_timeout: 30,
    }, (fb) => {
      this.exploreText = `${fb.stage}: ${fb.frontiers_left} frontiers left, ` +
        `${fb.explored_area_m2.toFixed(1)} m²`;
      this.render();
    });
    this.exploreGoal = id;
    this.exploreText = "exploring: looking for frontiers";
    this.render();
    result.then((r) => {
      if (this.exploreGoal !== id) return;
      const v = r.values || {};
      const done = r.status === 4 && !v.error_code;
      this.exploreText = done
        ? `exploring done: ${(v.explored_area_m2 ?? 0).toFixed(1)} m², back at the start`
        : `exploring ended: ${v.error_msg || `status ${r.status}`}`;
      this.exploreGoal = null;
      this.toast(this.exploreText, !done);
      this.render();
    }).catch((err) => {
      if (this.exploreGoal !== id) return;
      this.exploreGoal = null;
      this.exploreText = `explore refused: ${err.message}`;
      this.toast(this.exploreText, true);
      this.render();
    });
  }

  async stop() {
    this.setBusy(true);
    try {
      if (this.exploreGoal) {
        this.ros.cancelGoal(this.name("explore"), this.exploreGoal);
        this.exploreGoal = null;
        this.exploreText = "";
      }
      await this.call("slam/stop", {});
      this.toast("mapping stopped");
    } catch (err) {
      this.toast(`cannot stop mapping: ${err.message}`, true);
    } finally {
      this.setBusy(false);
    }
  }

  async save() {
    const name = this.els.saveName.value.trim();
    if (!NAME.test(name)) {
      this.toast("a map name is 1-64 letters, digits, _ . or -, not starting with . or -", true);
      return;
    }
    this.setBusy(true);
    try {
      const res = await this.call("slam/save", { name, type: "floor", levels: [] });
      this.toast(`saved map ${res.name || name}`);
      this.els.detail.dataset.saved = res.name || name;
    } catch (err) {
      this.toast(`cannot save: ${err.message}`, true);
    } finally {
      this.setBusy(false);
    }
  }

  setBusy(busy) {
    this.busy = busy;
    this.render();
  }

  render() {
    const s = this.state;
    const { els } = this;
    const on = this.mapping();
    els.state.textContent = s.state + (on && s.mode ? ` (${s.mode})` : "");
    els.state.dataset.state = s.state;
    const parts = [];
    if (on && s.width) {
      parts.push(`${s.width}×${s.height} cells, ${(s.area_m2 || 0).toFixed(1)} m² known`);
      parts.push(`${s.scans} scans, ${s.loop_closures} loop closures`);
    }
    if (this.exploreText) parts.push(this.exploreText);
    if (!on && s.message) parts.push(s.message);
    els.detail.textContent = parts.join(" · ");
    els.detail.dataset.explore = this.exploreText.startsWith("exploring done") ? "done" : "";
    els.start.disabled = this.busy || on;
    els.explore.disabled = this.busy || on;
    els.stop.disabled = this.busy || !on;
    els.save.disabled = this.busy || s.state !== "mapping";
  }
}
