// The dashboard: wires the rosbridge link to the map view, the panels and the teleop pad.

import { FleetPanel } from "./fleet.js";
import { MapView, yawOf } from "./map_view.js";
import { MappingPanel } from "./mapping.js";
import { Rosbridge } from "./rosbridge.js";
import { TaskPanel } from "./tasks.js";
import { Teleop } from "./teleop.js";

const $ = (id) => document.getElementById(id);

async function loadConfig() {
  const params = new URLSearchParams(location.search);
  let config = {};
  try {
    const res = await fetch("config.json", { cache: "no-store" });
    if (res.ok) config = await res.json();
  } catch (err) {
    config = {};
  }
  const port = config.rosbridge_port || 9090;
  const scheme = location.protocol === "https:" ? "wss" : "ws";
  return {
    rosbridge: params.get("rosbridge") || `${scheme}://${location.hostname || "127.0.0.1"}:${port}/`,
    ns: (params.get("ns") ?? config.namespace ?? "").replace(/\/+$/, ""),
    title: config.title || "",
    path: params.get("path"),
    robots: Array.isArray(config.robots) ? config.robots : null, // a fleet gateway's
    schedule: params.get("schedule") ?? config.schedule_server ?? "", // its traffic schedule
  };
}

function toast(text, error = false) {
  const el = $("toast");
  el.textContent = text;
  el.classList.toggle("error", error);
  el.hidden = false;
  clearTimeout(toast.timer);
  toast.timer = setTimeout(() => { el.hidden = true; }, 3500);
}

function fmt(x, digits = 2) {
  return Number.isFinite(x) ? x.toFixed(digits) : "–";
}

class Dashboard {
  constructor(config) {
    this.ns = config.ns;
    this.ros = new Rosbridge(config.rosbridge);
    this.view = new MapView($("map"));
    this.laser = { x: 0, y: 0, yaw: 0 };
    this.pose = null;
    this.points = [];
    this.goal = null; // {id, index}
    this.estop = false;
    this.gotoMode = false;
    this.mapName = "";
    this.pathName = null;
    this.wantedPath = config.path;
    $("robot-name").textContent = config.title || (this.ns ? this.ns.slice(1) : "zenros robot");
    this.teleop = new Teleop($("pad"), (v, w) => this.drive(v, w));
    this.taskPanel = new TaskPanel(this.ros, (call) => this.name(`tasks/${call}`), $("tasks"),
                                   $("tasks-empty"), (text) => toast(text, true));
    this.mapping = new MappingPanel(this.ros, (rel) => this.name(rel), this.view, {
      state: $("mapping-state"), detail: $("mapping-detail"), start: $("mapping-start"),
      explore: $("mapping-explore"), stop: $("mapping-stop"), save: $("mapping-save"),
      saveName: $("mapping-name"),
    }, toast);
    this.mapping.onPose = (p) => this.onPose(p);
    this.fleet = config.robots ? this.startFleet(config.robots, config.schedule) : null;
    this.wire();
    this.subscribe();
    this.ros.addEventListener("open", () => this.onOpen());
    this.ros.addEventListener("close", () => this.setLink(false));
  }

  name(rel) {
    return `${this.ns}/${rel}`;
  }

  // A fleet gateway: the fleet card and the other robots on the map; the list follows the
  // robots the gateway finds (config.json, every 5 s). Driving another reloads the page on it.
  startFleet(robots, schedule) {
    $("fleet-card").hidden = false;
    const fleet = new FleetPanel(this.ros, this.view, $("fleet"), this.ns.slice(1), (name) => {
      const params = new URLSearchParams(location.search);
      params.set("ns", `/${name}`);
      location.search = params.toString();
    }, (text) => toast(text, true));
    fleet.setRobots(robots);
    if (schedule) fleet.followSchedule(schedule);
    setInterval(async () => {
      try {
        const res = await fetch("config.json", { cache: "no-store" });
        if (res.ok) fleet.setRobots((await res.json()).robots || []);
      } catch (err) {
        // the gateway is restarting: the next round tries again
      }
    }, 5000);
    return fleet;
  }

  // -------------------------------------------------------------- wiring

  wire() {
    document.querySelectorAll("[data-zoom]").forEach((b) => b.addEventListener("click", () => {
      const c = this.view.canvas.getBoundingClientRect();
      if (b.dataset.zoom === "fit") this.view.fit();
      else this.view.zoom(b.dataset.zoom === "in" ? 1.3 : 1 / 1.3, c.width / 2, c.height / 2);
    }));
    document.querySelectorAll("[data-layer]").forEach((box) => box.addEventListener(
      "change", () => this.view.setLayer(box.dataset.layer, box.checked)));
    $("goto-mode").addEventListener("click", () => {
      this.gotoMode = !this.gotoMode;
      $("goto-mode").classList.toggle("active", this.gotoMode);
      document.querySelector(".map-card").classList.toggle("goto", this.gotoMode);
    });
    this.view.addEventListener("pick", (e) => {
      const { index, world } = e.detail;
      if (index >= 0) this.goToPoint(index);
      else if (this.gotoMode) this.navigate(world.x, world.y, this.pose ? this.pose.yaw : 0, null);
    });
    $("estop").addEventListener("click", () => this.toggleEstop());
    $("path-select").addEventListener("change", (e) => {
      this.pathName = e.target.value;
      this.wantedPath = e.target.value;
      this.refreshPoints();
    });
    $("cancel-goal").addEventListener("click", () => this.cancelGoal());
    $("camera-select").addEventListener("change", (e) => this.watchCamera(e.target.value));
  }

  subscribe() {
    const ros = this.ros;
    ros.subscribe(this.name("map"), "nav_msgs/OccupancyGrid", (m) => {
      this.view.setMap(m);
      this.refreshMapData();
    });
    ros.subscribe(this.name("global_costmap/costmap"), "nav_msgs/OccupancyGrid",
                  (m) => this.view.setCostmap(m), { throttle_rate: 2000, queue_length: 1 });
    ros.subscribe(this.name("robot_pose"), "geometry_msgs/PoseWithCovarianceStamped",
                  (m) => { if (!this.mapping.mapping()) this.onPose(m.pose.pose); },
                  { throttle_rate: 50, queue_length: 1 }); // while mapping: slam/pose
    ros.subscribe(this.name("scan"), "sensor_msgs/LaserScan", (m) => this.onScan(m),
                  { throttle_rate: 150, queue_length: 1 });
    ros.subscribe(this.name("plan"), "nav_msgs/Path", (m) => this.view.setPlan(
      m.poses.map((p) => ({ x: p.pose.position.x, y: p.pose.position.y }))));
    ros.subscribe(this.name("battery_state"), "sensor_msgs/BatteryState",
                  (m) => this.onBattery(m), { throttle_rate: 1000, queue_length: 1 });
    ros.subscribe(this.name("chassis/state"), "zenros_msgs/ChassisState",
                  (m) => this.onChassis(m), { throttle_rate: 200, queue_length: 1 });
    ros.subscribe(this.name("nav/status"), "zenros_msgs/NavStatus", (m) => this.onNav(m));
    ros.subscribe(this.name("tasks/status"), "zenros_msgs/TaskStatus",
                  (m) => this.taskPanel.onStatus(m));
    ros.subscribe("/tf_static", "tf2_msgs/TFMessage", (m) => this.onTfStatic(m));
    this.mapping.subscribe();
    this.watchCamera($("camera-select").value);
    // a robot of a fleet keeps its own tree (/<robot>/tf_static, docs/fleet.md)
    if (this.ns) ros.subscribe(this.name("tf_static"), "tf2_msgs/TFMessage", (m) => this.onTfStatic(m));
  }

  // The chosen camera's JPEG topic, 5 frames a second at most, or none ("": off; the
  // simulator renders a camera only while someone watches it, docs/chassis.md, Cameras).
  watchCamera(which) {
    if (this.cameraOff) this.cameraOff();
    this.cameraOff = null;
    const img = $("camera");
    if (!which) {  // off: nothing rendered for us
      img.removeAttribute("src");
      $("camera-empty").hidden = false;
      return;
    }
    this.cameraOff = this.ros.subscribe(
      this.name(`${which}/image_raw/compressed`), "sensor_msgs/CompressedImage", (m) => {
        img.src = `data:image/jpeg;base64,${m.data}`;
        $("camera-empty").hidden = true;
      }, { throttle_rate: 200, queue_length: 1 });
  }

  onOpen() {
    this.setLink(true);
    this.refreshMapData();
    this.taskPanel.refresh();
  }

  setLink(up) {
    $("link").classList.toggle("up", up);
    $("link").classList.toggle("down", !up);
    $("link-text").textContent = up ? "live" : "offline";
  }

  // -------------------------------------------------------------- live data

  onPose(p) {
    const yaw = yawOf(p.orientation);
    this.pose = { x: p.position.x, y: p.position.y, yaw };
    this.view.setRobot(this.pose.x, this.pose.y, yaw);
    const pose = $("pose");
    pose.textContent = `x ${fmt(this.pose.x)} m   y ${fmt(this.pose.y)} m   yaw ${Math.round(yaw * 180 / Math.PI) || 0}°`;
    pose.dataset.x = String(this.pose.x);
    pose.dataset.y = String(this.pose.y);
    pose.dataset.yaw = String(yaw);
  }

  onTfStatic(m) {
    for (const t of m.transforms) {
      if (t.child_frame_id.endsWith("laser")) {
        const tr = t.transform;
        this.laser = { x: tr.translation.x, y: tr.translation.y, yaw: yawOf(tr.rotation) };
      }
    }
  }

  onScan(m) {
    if (!this.pose) return;
    const { x, y, yaw } = this.pose;
    const lx = x + Math.cos(yaw) * this.laser.x - Math.sin(yaw) * this.laser.y;
    const ly = y + Math.sin(yaw) * this.laser.x + Math.cos(yaw) * this.laser.y;
    const pts = [];
    m.ranges.forEach((r, i) => {
      if (r === null || !(r >= m.range_min && r <= m.range_max)) return;
      const a = yaw + this.laser.yaw + m.angle_min + i * m.angle_increment;
      pts.push({ x: lx + r * Math.cos(a), y: ly + r * Math.sin(a) });
    });
    this.view.setScan(pts);
  }

  onBattery(m) {
    const pct = Math.round((m.percentage ?? 0) * 100);
    $("battery").textContent = Number.isFinite(pct) ? `${pct}%` : "–";
    const fill = $("battery-fill");
    fill.style.width = `${Math.max(0, Math.min(100, pct))}%`;
    fill.style.background = pct < 20 ? "var(--bad)" : pct < 40 ? "var(--warn)" : "var(--ok)";
  }

  onChassis(m) {
    this.estop = m.estop;
    const btn = $("estop");
    btn.classList.toggle("engaged", m.estop);
    btn.textContent = m.estop ? "RELEASE" : "E-STOP";
    btn.dataset.engaged = m.estop ? "1" : "0";
    const banner = $("banner");
    banner.hidden = !m.estop && !m.bumper;
    banner.textContent = m.estop ? "Emergency stop engaged" : m.bumper ? "Bumper pressed" : "";
    $("charging").textContent = m.charging ? "charging" : m.docked ? "docked" : "no";
  }

  onNav(m) {
    $("nav-state").textContent = m.state;
    $("robot-state").textContent = m.localized ? m.state : `${m.state} (not localized)`;
    $("robot-state").dataset.state = m.state;
    $("target").textContent = m.target_distance >= 0 ? `${fmt(m.target_distance, 1)} m to go` : "–";
    $("map-name").textContent = m.map_name || "–";
    if (m.map_name && m.map_name !== this.mapName) {
      this.mapName = m.map_name;
      this.refreshPoints();
    }
  }

  // -------------------------------------------------------------- nav points, walls

  async refreshMapData() {
    await this.refreshPoints();
    try {
      const res = await this.ros.callService(this.name("get_virtual_walls"), {});
      this.view.setWalls((res.walls || []).map((w) => w.points));
    } catch (err) {
      this.view.setWalls([]);
    }
  }

  async refreshPoints() {
    let paths = [];
    try {
      const res = await this.ros.callService(this.name("list_paths"), { map_name: this.mapName || "" });
      paths = (res.paths || []).filter((p) => !this.mapName || p.map_name === this.mapName)
        .map((p) => p.path_name);
    } catch (err) {
      paths = [];
    }
    if (!paths.includes(this.pathName)) {
      this.pathName = paths.includes(this.wantedPath) ? this.wantedPath : paths[0] ?? null;
    }
    const select = $("path-select");
    select.replaceChildren(...paths.map((name) => {
      const o = document.createElement("option");
      o.value = name;
      o.textContent = name;
      o.selected = name === this.pathName;
      return o;
    }));
    select.hidden = paths.length < 2;
    this.points = [];
    if (this.pathName !== null) {
      try {
        const res = await this.ros.callService(this.name("get_nav_points"),
                                               { map_name: this.mapName || "", path_name: this.pathName });
        this.points = res.points || [];
      } catch (err) {
        this.points = [];
      }
    }
    this.view.setPoints(this.points);
    this.renderPoints();
  }

  renderPoints() {
    const list = $("points");
    list.replaceChildren();
    $("points-empty").hidden = this.points.length > 0;
    this.points.forEach((p, i) => {
      const li = document.createElement("li");
      li.dataset.index = String(i);
      if (this.goal && this.goal.index === i) li.classList.add("current");
      const name = document.createElement("span");
      name.className = "name";
      name.textContent = p.name || `Point ${i}`;
      const sub = document.createElement("span");
      sub.className = "sub";
      sub.textContent = `${fmt(p.x, 1)}, ${fmt(p.y, 1)}`;
      const go = document.createElement("button");
      go.type = "button";
      go.textContent = "Go";
      go.addEventListener("click", () => this.goToPoint(i));
      li.append(name, sub, go);
      list.append(li);
    });
  }

  goToPoint(index) {
    const p = this.points[index];
    if (p) this.navigate(p.x, p.y, p.theta, index, p.name || `point ${index}`);
  }

  navigate(x, y, theta, index, label = null) {
    if (this.goal) this.ros.cancelGoal(this.name("navigate_to_pose"), this.goal.id);
    const goal = {
      pose: {
        header: { frame_id: "map" },
        pose: {
          position: { x, y, z: 0 },
          orientation: { x: 0, y: 0, z: Math.sin(theta / 2), w: Math.cos(theta / 2) },
        },
      },
    };
    const text = label || `(${fmt(x, 1)}, ${fmt(y, 1)})`;
    const { id, result } = this.ros.sendGoal(this.name("navigate_to_pose"),
                                             "nav2_msgs/NavigateToPose", goal, () => {});
    this.goal = { id, index };
    this.view.setActivePoint(index);
    this.renderPoints();
    $("goal-text").textContent = `→ ${text}`;
    result.then((r) => {
      if (this.goal && this.goal.id === id) {
        const done = { 4: "arrived at", 5: "canceled:", 6: "failed to reach" }[r.status] || "ended:";
        toast(`${done} ${text}`, r.status !== 4);
        this.clearGoal();
      }
    }).catch((err) => {
      if (this.goal && this.goal.id === id) {
        toast(`goal refused: ${err.message}`, true);
        this.clearGoal();
      }
    });
  }

  clearGoal() {
    this.goal = null;
    this.view.setActivePoint(null);
    $("goal-text").textContent = "";
    this.renderPoints();
  }

  cancelGoal() {
    if (this.goal) this.ros.cancelGoal(this.name("navigate_to_pose"), this.goal.id);
    else toast("no navigation goal from this page");
  }

  // -------------------------------------------------------------- e-stop, teleop

  async toggleEstop() {
    const engage = !this.estop;
    try {
      const res = await this.ros.callService(this.name("chassis/set_estop"), { data: engage });
      if (!res.success) toast(res.message || "e-stop refused", true);
      if (engage && this.goal) this.cancelGoal();
    } catch (err) {
      toast(`e-stop: ${err.message}`, true);
    }
  }

  drive(v, w) {
    this.ros.publish(this.name("cmd_vel"), "geometry_msgs/Twist", {
      linear: { x: v, y: 0, z: 0 }, angular: { x: 0, y: 0, z: w },
    });
  }
}

loadConfig().then((config) => {
  window.dashboard = new Dashboard(config);
});
