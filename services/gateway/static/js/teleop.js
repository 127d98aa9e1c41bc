// Teleop: an on-screen joystick (pointer/touch) and the keyboard (WASD / arrows) drive
// cmd_vel at 10 Hz while held; letting go sends one zero command.

const KEYS = {
  ArrowUp: [1, 0], KeyW: [1, 0], ArrowDown: [-1, 0], KeyS: [-1, 0],
  ArrowLeft: [0, 1], KeyA: [0, 1], ArrowRight: [0, -1], KeyD: [0, -1],
};

export class Teleop {
  constructor(pad, send, { maxLinear = 0.5, maxAngular = 1.2 } = {}) {
    this.pad = pad;
    this.knob = pad.querySelector(".knob");
    this.send = send;
    this.maxLinear = maxLinear;
    this.maxAngular = maxAngular;
    this.stick = null; // {v, w} from the joystick, or null
    this.keys = new Set();
    this.timer = null;
    this.installPad();
    this.installKeys();
  }

  command() {
    if (this.stick) return this.stick;
    let v = 0;
    let w = 0;
    for (const code of this.keys) {
      v += KEYS[code][0];
      w += KEYS[code][1];
    }
    return { v: Math.sign(v) * this.maxLinear * 0.6, w: Math.sign(w) * this.maxAngular * 0.6 };
  }

  active() {
    return this.stick !== null || this.keys.size > 0;
  }

  update() {
    if (this.active() && this.timer === null) {
      this.tick();
      this.timer = setInterval(() => this.tick(), 100);
    } else if (!this.active() && this.timer !== null) {
      clearInterval(this.timer);
      this.timer = null;
      this.send(0, 0);
    }
  }

  tick() {
    const { v, w } = this.command();
    this.send(v, w);
  }

  installPad() {
    const pad = this.pad;
    const move = (e) => {
      const r = pad.getBoundingClientRect();
      const radius = r.width / 2;
      let dx = (e.clientX - r.left - radius) / radius;
      let dy = (e.clientY - r.top - radius) / radius;
      const d = Math.hypot(dx, dy);
      if (d > 1) { dx /= d; dy /= d; }
      this.knob.style.transform = `translate(${dx * radius * 0.6}px, ${dy * radius * 0.6}px)`;
      this.stick = { v: -dy * this.maxLinear, w: -dx * this.maxAngular };
    };
    pad.addEventListener("pointerdown", (e) => {
      pad.setPointerCapture(e.pointerId);
      pad.classList.add("held");
      move(e);
      this.update();
    });
    pad.addEventListener("pointermove", (e) => {
      if (this.stick !== null) move(e);
    });
    const release = () => {
      pad.classList.remove("held");
      this.knob.style.transform = "";
      this.stick = null;
      this.update();
    };
    pad.addEventListener("pointerup", release);
    pad.addEventListener("pointercancel", release);
  }

  installKeys() {
    const typing = (e) => ["INPUT", "TEXTAREA", "SELECT"].includes(e.target.tagName);
    window.addEventListener("keydown", (e) => {
      if (!(e.code in KEYS) || typing(e)) return;
      e.preventDefault();
      this.keys.add(e.code);
      this.update();
    });
    window.addEventListener("keyup", (e) => {
      if (!this.keys.delete(e.code)) return;
      this.update();
    });
    window.addEventListener("blur", () => {
      this.keys.clear();
      this.update();
    });
  }
}
