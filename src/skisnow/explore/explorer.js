// skisnow explorer: one self-contained page, no server, no network. The data are a gzip-compressed
// binary blob (base64) described by the JSON manifest; arrays are decoded with the browser's own
// DecompressionStream. Curves are stored as int16 deltas of a per-point scaled quantisation, byte
// planes split (see skisnow.explore._pack): decoding is undo-shuffle, cumulative sum, scale.
"use strict";
(function () {
  const META = JSON.parse(document.getElementById("skisnow-meta").textContent);
  const ZONE_COLORS = ["#d95f02", "#1b9e77", "#7570b3"]; // rear, middle, front
  const ZONE_NAMES = ["rear", "middle", "front", "total", "kick"];
  const ZONE_LABELS = { kick: "between the kick-zone marks" };
  const state = { ski: 0, model: 0, mass: 0, pos: 0, mod: 0 };
  let DATA = null;

  function b64bytes(text) {
    const bin = atob(text.trim());
    const out = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) out[i] = bin.charCodeAt(i);
    return out;
  }

  async function gunzip(bytes) {
    const stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("gzip"));
    return new Uint8Array(await new Response(stream).arrayBuffer());
  }

  function view(buf, a) {
    const n = a.shape.reduce((p, q) => p * q, 1);
    const bytes = buf.slice(a.offset, a.offset + a.nbytes);
    if (a.codec === "delta16") {
      // byte planes (all low bytes, then all high bytes) of int16 deltas along the last axis
      const m = n, lo = bytes.subarray(0, m), hi = bytes.subarray(m, 2 * m);
      const out = new Float32Array(m), len = a.shape[a.shape.length - 1];
      for (let r = 0; r < m / len; r++) {
        let acc = 0;
        for (let i = r * len; i < (r + 1) * len; i++) {
          let d = lo[i] | (hi[i] << 8);
          if (d & 0x8000) d -= 0x10000;
          acc += d;
          out[i] = acc;
        }
      }
      return out;
    }
    const T = { float32: Float32Array, uint8: Uint8Array, int16: Int16Array, int32: Int32Array }[a.dtype];
    return new T(bytes.buffer, bytes.byteOffset, n);
  }

  async function decode() {
    const raw = await gunzip(b64bytes(document.getElementById("skisnow-blob").textContent));
    const data = {};
    for (const [name, a] of Object.entries(META.arrays)) data[name] = { a, v: view(raw, a) };
    return data;
  }

  // flat index of the grid point (ski, model, mass, pos, mod)
  function point() {
    const g = META.grid;
    return (((state.ski * g.model.length + state.model) * g.mass_kg.length + state.mass) *
      g.load_position_mm.length + state.pos) * g.snow_modulus_mpa.length + state.mod;
  }
  function row(name, p) {
    const d = DATA[name], len = d.a.shape[d.a.shape.length - 1];
    return d.v.subarray(p * len, (p + 1) * len);
  }
  function curve(name, p) {
    const q = row(name, p), s = DATA[name + "_scale"].v[p], out = new Float32Array(q.length);
    for (let i = 0; i < q.length; i++) out[i] = q[i] * s;
    return out;
  }
  function metric(name, p, z) { return DATA[name].v[p * ZONE_NAMES.length + z]; }

  // ---- drawing ------------------------------------------------------------------------------
  function setupCanvas(id) {
    const c = document.getElementById(id), r = window.devicePixelRatio || 1;
    const w = c.parentElement.clientWidth, h = Math.max(150, Math.min(260, w * 0.42));
    c.width = w * r; c.height = h * r; c.style.width = w + "px"; c.style.height = h + "px";
    const ctx = c.getContext("2d"); ctx.setTransform(r, 0, 0, r, 0, 0);
    ctx.clearRect(0, 0, w, h); ctx.font = "11px sans-serif";
    return { ctx, w, h };
  }
  function axes(ctx, w, h, x0, x1, y0, y1, xlabel, ylabel) {
    const L = 48, R = 10, T = 10, B = 30;
    const sx = (x) => L + ((x - x0) / (x1 - x0)) * (w - L - R);
    const sy = (y) => h - B - ((y - y0) / (y1 - y0)) * (h - T - B);
    ctx.strokeStyle = "#888"; ctx.fillStyle = "#333"; ctx.lineWidth = 1;
    ctx.strokeRect(L, T, w - L - R, h - T - B);
    ctx.textAlign = "center";
    for (const t of ticks(x0, x1, 6)) { ctx.fillText(fmt(t), sx(t), h - B + 13); }
    ctx.fillText(xlabel, (L + w - R) / 2, h - 3);
    ctx.textAlign = "right";
    for (const t of ticks(y0, y1, 4)) { ctx.fillText(fmt(t), L - 4, sy(t) + 4); }
    ctx.save(); ctx.translate(11, (T + h - B) / 2); ctx.rotate(-Math.PI / 2);
    ctx.textAlign = "center"; ctx.fillText(ylabel, 0, 0); ctx.restore();
    return { sx, sy, L, R, T, B };
  }
  function ticks(a, b, n) {
    const step = Math.pow(10, Math.floor(Math.log10((b - a) / n)));
    const m = [1, 2, 5, 10].find((k) => (b - a) / (k * step) <= n) * step;
    const out = [];
    for (let t = Math.ceil(a / m) * m; t <= b + 1e-9 * m; t += m) out.push(t);
    return out;
  }
  function fmt(v) { return Math.abs(v) >= 100 || v === 0 ? v.toFixed(0) : v.toPrecision(2); }
  function line(ctx, xs, ys, sx, sy, color, width) {
    ctx.strokeStyle = color; ctx.lineWidth = width; ctx.beginPath();
    for (let i = 0; i < xs.length; i++) (i ? ctx.lineTo : ctx.moveTo).call(ctx, sx(xs[i]), sy(ys[i]));
    ctx.stroke();
  }
  function shadeZones(ctx, xs, zone, sx, top, bottom) {
    const dx = xs[1] - xs[0];
    for (let i = 0; i < xs.length; i++) {
      if (!zone[i]) continue;
      ctx.fillStyle = ZONE_COLORS[zone[i] - 1] + "40";
      ctx.fillRect(sx(xs[i] - dx / 2), top, sx(xs[i] + dx / 2) - sx(xs[i] - dx / 2) + 0.5, bottom - top);
    }
  }

  function drawProfile(p, xs, zone) {
    const { ctx, w, h } = setupCanvas("profile");
    const bottom = curve("base_um", p), snow = curve("snow_um", p);
    const zoom = document.getElementById("zoom").checked;
    let lo = 0, hi = 0;
    for (let i = 0; i < xs.length; i++) { lo = Math.min(lo, snow[i], bottom[i]); hi = Math.max(hi, bottom[i]); }
    if (zoom) hi = Math.min(hi, Math.max(-3 * lo, 100));
    const ax = axes(ctx, w, h, xs[0], xs[xs.length - 1], lo * 1.05 - 1, hi * 1.02 + 1, "x [mm] (0 = balance point, tip →)", "height [µm]");
    shadeZones(ctx, xs, zone, ax.sx, ax.T, h - ax.B);
    ctx.save(); ctx.beginPath(); ctx.rect(ax.L, ax.T, w - ax.L - ax.R, h - ax.T - ax.B); ctx.clip();
    line(ctx, xs, snow, ax.sx, ax.sy, "#5aa0d8", 2);
    line(ctx, xs, bottom, ax.sx, ax.sy, "#222", 1.5);
    const xm = META.grid.load_position_mm[state.pos];
    ctx.fillStyle = "#c00"; ctx.beginPath(); ctx.moveTo(ax.sx(xm), ax.T);
    ctx.lineTo(ax.sx(xm) - 5, ax.T + 10); ctx.lineTo(ax.sx(xm) + 5, ax.T + 10); ctx.fill();
    ctx.restore();
  }

  function drawPressure(p, xs, zone) {
    const { ctx, w, h } = setupCanvas("pressure");
    const pr = curve("pressure_kpa", p);
    let hi = 1; for (const v of pr) hi = Math.max(hi, v);
    const ax = axes(ctx, w, h, xs[0], xs[xs.length - 1], 0, hi * 1.08, "x [mm]", "pressure [kPa]");
    shadeZones(ctx, xs, zone, ax.sx, ax.T, h - ax.B);
    line(ctx, xs, pr, ax.sx, ax.sy, "#14365d", 1.5);
  }

  function drawMap(id, name, label) {
    const { ctx, w, h } = setupCanvas(id);
    const g = META.grid, nm = g.mass_kg.length, ne = g.snow_modulus_mpa.length;
    const ax = axes(ctx, w, h, g.mass_kg[0], g.mass_kg[nm - 1], g.snow_modulus_mpa[0], g.snow_modulus_mpa[ne - 1], "mass [kg]", "E_snow [MPa]");
    let lo = Infinity, hi = -Infinity; const vals = [];
    for (let a = 0; a < nm; a++) for (let e = 0; e < ne; e++) {
      const pt = (((state.ski * g.model.length + state.model) * nm + a) * g.load_position_mm.length + state.pos) * ne + e;
      const v = metric(name, pt, 3); vals.push(v);
      if (isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    }
    const cw = (w - ax.L - ax.R) / nm, ch = (h - ax.T - ax.B) / ne;
    for (let a = 0; a < nm; a++) for (let e = 0; e < ne; e++) {
      const v = vals[a * ne + e], t = isFinite(v) ? (v - lo) / (hi - lo || 1) : -1;
      ctx.fillStyle = t < 0 ? "#ddd" : `hsl(${240 - 200 * t},70%,${35 + 30 * t}%)`;
      ctx.fillRect(ax.L + a * cw, h - ax.B - (e + 1) * ch, cw + 0.5, ch + 0.5);
    }
    ctx.strokeStyle = "#fff"; ctx.lineWidth = 2;
    ctx.strokeRect(ax.L + state.mass * cw, h - ax.B - (state.mod + 1) * ch, cw, ch);
    document.getElementById(id + "-label").textContent = `${label}: ${fmt(lo)} (blue) – ${fmt(hi)} (yellow)`;
  }

  function table(p) {
    const rows = ZONE_NAMES.map((z, q) => {
      const cell = (n, d) => { const v = metric(n, p, q); return isFinite(v) ? v.toFixed(d) : "–"; };
      return `<tr data-zone="${z}"><td>${ZONE_LABELS[z] || z}</td><td class="length">${cell("length_mm", 1)}</td>` +
        `<td>${cell("area_cm2", 1)}</td><td>${cell("mean_pressure_kpa", 1)}</td>` +
        `<td>${cell("max_pressure_kpa", 1)}</td><td>${(100 * metric("load_share", p, q)).toFixed(1)}</td>` +
        `<td>${metric("patches", p, q)}</td></tr>`;
    });
    document.getElementById("zones").innerHTML = rows.join("");
    const conv = DATA.converged.v[p];
    const kick = metric("length_mm", p, 4);
    document.getElementById("status").textContent =
      (conv ? "converged" : "NOT converged / load not carried") +
      (kick > 0 ? ` · the kick zone touches the snow over ${kick.toFixed(1)} mm` : "");
  }

  function labels() {
    const g = META.grid;
    document.getElementById("mass-value").textContent = g.mass_kg[state.mass] + " kg";
    document.getElementById("pos-value").textContent = g.load_position_mm[state.pos] + " mm";
    document.getElementById("mod-value").textContent = g.snow_modulus_mpa[state.mod] + " MPa";
  }

  function render() {
    labels();
    const p = point(), xs = DATA["x_mm"].v.subarray(state.ski * META.n_stations, (state.ski + 1) * META.n_stations);
    const zone = row("zone_code", p);
    drawProfile(p, xs, zone); drawPressure(p, xs, zone); table(p);
    drawMap("map-area", "area_cm2", "total contact area [cm²]");
    drawMap("map-pressure", "mean_pressure_kpa", "mean pressure [kPa]");
    document.body.dataset.point = String(p);
  }

  function bind(id, key) {
    const el = document.getElementById(id);
    const update = () => { state[key] = Number(el.value); render(); };
    el.addEventListener("input", update);
    el.addEventListener("change", update);
    state[key] = Number(el.value);
  }

  async function main() {
    const g = META.grid;
    document.getElementById("mass").max = g.mass_kg.length - 1;
    document.getElementById("pos").max = g.load_position_mm.length - 1;
    document.getElementById("mod").max = g.snow_modulus_mpa.length - 1;
    for (const id of ["mass", "pos", "mod"]) {
      const el = document.getElementById(id);
      el.value = el.dataset.initial;
    }
    const skiSel = document.getElementById("ski"), modelSel = document.getElementById("model");
    g.ski.forEach((s, i) => skiSel.add(new Option(s, i)));
    g.model.forEach((s, i) => modelSel.add(new Option(s, i)));
    modelSel.disabled = g.model.length < 2;
    bind("mass", "mass"); bind("pos", "pos"); bind("mod", "mod"); bind("ski", "ski"); bind("model", "model");
    document.getElementById("zoom").addEventListener("change", render);
    DATA = await decode();
    window.addEventListener("resize", render);
    render();
    document.body.dataset.ready = "1";
  }
  main().catch((e) => { document.getElementById("status").textContent = "error: " + e; throw e; });
})();
