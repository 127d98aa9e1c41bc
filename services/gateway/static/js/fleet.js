// The fleet view of a fleet gateway (config.json lists its robots): every robot on the map
// and in a list with its state, battery and e-stop; pick one to drive it with the page,
// e-stop or release any of them from its row. With the fleet's schedule server named, the
// segments each robot in schedule mode holds are drawn on the map and its row says whom it
// waits for.

function pct(m) {
  const p = m.percentage ?? 0;
  return Math.round(p <= 1 ? p * 100 : p);
}

export class FleetPanel {
  // ros: the Rosbridge link; view: the MapView; list: the <ol> of rows; current: the name
  // of the robot the page drives; onPick(name): drive that one; onError(text): a toast.
  constructor(ros, view, list, current, onPick, onError) {
    this.ros = ros;
    this.view = view;
    this.list = list;
    this.current = current;
    this.onPick = onPick;
    this.onError = onError;
    this.robots = new Map(); // name -> {name, pose, state, battery, estop, traffic, row}
    this.held = new Set(); // robots seen holding a segment since the page loaded
  }

  // the schedule server's reservations (latched): who holds which cells, who waits for whom
  followSchedule(server) {
    this.ros.subscribe(`/schedule/${server}/reservations`, "zenros_msgs/TrafficReservations",
                       (m) => this.setTraffic(m), { throttle_rate: 200, queue_length: 1 });
  }

  setTraffic(m) {
    const drawn = [];
    const byRobot = new Map();
    for (const t of m.robots || []) {
      const cells = (t.holds || []).flatMap((h) => h.cells || []);
      if (cells.length) this.held.add(t.robot);
      drawn.push({ robot: t.robot, cells, size: m.cell_size || 0.5,
                   stop: t.stop && t.stop.length ? t.stop[0] : null });
      byRobot.set(t.robot, t);
    }
    this.view.setReservations(drawn);
    for (const r of this.robots.values()) {
      const t = byRobot.get(r.name);
      r.traffic = !t ? "" : t.must_yield ? "yields"
        : t.wait_for ? `waits for ${t.wait_for}` : `holds ${(t.holds || []).length}`;
      this.update(r);
    }
  }

  setRobots(names) {
    for (const name of names) if (!this.robots.has(name)) this.add(name);
  }

  add(name) {
    const r = { name, pose: null, state: "–", battery: null, estop: false, traffic: "",
                row: this.build(name) };
    this.robots.set(name, r);
    this.list.append(r.row);
    const ros = this.ros;
    ros.subscribe(`/${name}/robot_pose`, "geometry_msgs/PoseWithCovarianceStamped", (m) => {
      const p = m.pose.pose;
      const q = p.orientation;
      r.pose = { x: p.position.x, y: p.position.y,
                 yaw: Math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z)) };
      this.drawOthers();
    }, { throttle_rate: 200, queue_length: 1 });
    ros.subscribe(`/${name}/battery_state`, "sensor_msgs/BatteryState", (m) => {
      r.battery = pct(m);
      this.update(r);
    }, { throttle_rate: 1000, queue_length: 1 });
    ros.subscribe(`/${name}/chassis/state`, "zenros_msgs/ChassisState", (m) => {
      r.estop = m.estop;
      this.update(r);
      this.drawOthers();
    }, { throttle_rate: 200, queue_length: 1 });
    ros.subscribe(`/${name}/nav/status`, "zenros_msgs/NavStatus", (m) => {
      r.state = m.state;
      this.update(r);
    }, { throttle_rate: 500, queue_length: 1 });
    this.update(r);
  }

  build(name) {
    const li = document.createElement("li");
    li.className = "robot";
    li.dataset.robot = name;
    if (name === this.current) li.classList.add("current");
    const label = document.createElement("span");
    label.className = "name";
    label.textContent = name;
    const sub = document.createElement("span");
    sub.className = "sub";
    const stop = document.createElement("button");
    stop.type = "button";
    stop.className = "estop-small";
    stop.addEventListener("click", (e) => {
      e.stopPropagation();
      this.toggleEstop(name);
    });
    const drive = document.createElement("button");
    drive.type = "button";
    drive.className = "drive";
    drive.textContent = name === this.current ? "Driving" : "Drive";
    drive.disabled = name === this.current;
    drive.addEventListener("click", () => this.onPick(name));
    li.append(label, sub, stop, drive);
    return li;
  }

  update(r) {
    const [, sub, stop] = r.row.children;
    const battery = r.battery === null ? "–" : `${r.battery}%`;
    const traffic = r.traffic ? ` · ${r.traffic}` : "";
    sub.textContent = `${r.estop ? "E-STOP" : r.state} · ${battery}${traffic}`;
    r.row.dataset.state = r.state;
    r.row.dataset.traffic = r.traffic;
    r.row.dataset.battery = r.battery === null ? "" : String(r.battery);
    r.row.dataset.estop = r.estop ? "1" : "0";
    r.row.classList.toggle("stopped", r.estop);
    stop.textContent = r.estop ? "Release" : "E-stop";
  }

  drawOthers() {
    const others = [];
    for (const r of this.robots.values()) {
      if (r.name !== this.current && r.pose) others.push({ name: r.name, estop: r.estop, ...r.pose });
    }
    this.view.setOthers(others);
  }

  async toggleEstop(name) {
    const r = this.robots.get(name);
    try {
      const res = await this.ros.callService(`/${name}/chassis/set_estop`, { data: !r.estop });
      if (!res.success) this.onError(res.message || `${name}: e-stop refused`);
    } catch (err) {
      this.onError(`${name} e-stop: ${err.message}`);
    }
  }
}
