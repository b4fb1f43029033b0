// skisnow explorer: one self-contained page, no server, no network. The data are a gzip-compressed
// binary blob (base64) described by the JSON manifest; arrays are decoded with the browser's own
// DecompressionStream. Curves are stored as int16 deltas of a per-point scaled quantisation, byte
// planes split (see skisnow.explore._pack): decoding is undo-shuffle, cumulative sum, scale.
"use strict";
(function () {
  const META = JSON.parse(document.getElementById("skisnow-meta").textContent);
  // the palette, names and colour map come from skisnow.plot (one palette for figures and page)
  const PALETTE = META.palette, LABELS = META.labels, CMAP = META.cmap;
  const ZONE_NAMES = META.zones;
  const CODED = ["rear", "middle", "front"]; // zone_code 1, 2, 3 of each display station
  const state = { ski: 0, model: 0, base: 0, mass: 0, pos: 0, mod: 0 };
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
  function point() { return pointAt(state.mass, state.mod); }
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
  function zoneIndex(name) { return ZONE_NAMES.indexOf(name); }
  function pointAt(a, e) { // flat index of (mass a, modulus e) at the current ski, model, base, position
    const g = META.grid;
    return ((((state.ski * g.model.length + state.model) * g.base.length + state.base) *
      g.mass_kg.length + a) * g.load_position_mm.length + state.pos) * g.snow_modulus_mpa.length + e;
  }

  function drawReal(p, xs, zone) { // the real contact of the base shown (with base textures)
    const frac = curve("real_fraction_percent", p), sep = curve("separation_log10_um", p);
    {
      const { ctx, w, h } = setupCanvas("real-fraction");
      let hi = 0.01; for (const v of frac) hi = Math.max(hi, v);
      const ax = axes(ctx, w, h, xs[0], xs[xs.length - 1], 0, hi * 1.1, "x [mm]", "real area [% of apparent]");
      shadeZones(ctx, xs, zone, ax.sx, ax.T, h - ax.B);
      line(ctx, xs, frac, ax.sx, ax.sy, "#16a085", 1.5);
    }
    {
      const { ctx, w, h } = setupCanvas("separation");
      let lo = Infinity, hi = -Infinity;
      for (const v of sep) { if (isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); } }
      const ax = axes(ctx, w, h, xs[0], xs[xs.length - 1], Math.floor(lo), Math.ceil(hi), "x [mm]", "log10 separation [µm]");
      shadeZones(ctx, xs, zone, ax.sx, ax.T, h - ax.B);
      line(ctx, xs, sep, ax.sx, ax.sy, "#1f5fbf", 1.5);
    }
    const tq = ZONE_NAMES.indexOf("total");
    const area = metric("real_area_grains_mm2", p, tq), visc = metric("viscous_force_n", p, tq);
    const mu = DATA.mu.v[p], mul = DATA.mu_lubricated.v[p];
    document.getElementById("real-note").textContent =
      `base ${META.grid.base[state.base]} on ${META.snow}: real area ${area.toFixed(1)} mm² ` +
      `(bearing model), viscous drag ${visc.toFixed(1)} N, µ ${mul.toFixed(3)}–${mu.toFixed(3)} ` +
      "(lubricated–dry contact spots; cited default parameters, an estimate, not a measurement)";
  }

  // ---- drawing ------------------------------------------------------------------------------
  function setupCanvas(id, minH) {
    const c = document.getElementById(id), r = window.devicePixelRatio || 1;
    const w = c.parentElement.clientWidth, h = Math.max(minH || 170, Math.min(280, w * 0.45));
    c.width = w * r; c.height = h * r; c.style.width = w + "px"; c.style.height = h + "px";
    const ctx = c.getContext("2d"); ctx.setTransform(r, 0, 0, r, 0, 0);
    ctx.clearRect(0, 0, w, h); ctx.font = "12px sans-serif";
    return { c, ctx, w, h };
  }
  function axes(ctx, w, h, x0, x1, y0, y1, xlabel, ylabel, opts) {
    const o = opts || {}, L = 52, R = o.R || 10, T = 10, B = 34;
    const sx = (x) => L + ((x - x0) / (x1 - x0)) * (w - L - R);
    const sy = (y) => h - B - ((y - y0) / (y1 - y0)) * (h - T - B);
    ctx.strokeStyle = "#888"; ctx.fillStyle = "#333"; ctx.lineWidth = 1;
    ctx.strokeRect(L, T, w - L - R, h - T - B);
    ctx.textAlign = "center";
    for (const t of (o.xticks || ticks(x0, x1, Math.max(3, Math.floor((w - L - R) / 60))))) ctx.fillText(fmt(t), sx(t), h - B + 14);
    ctx.fillText(xlabel, (L + w - R) / 2, h - 4);
    ctx.textAlign = "right";
    for (const t of (o.yticks || ticks(y0, y1, 4))) ctx.fillText(fmt(t), L - 4, sy(t) + 4);
    ctx.save(); ctx.translate(12, (T + h - B) / 2); ctx.rotate(-Math.PI / 2);
    ctx.textAlign = "center"; ctx.fillText(ylabel, 0, 0); ctx.restore();
    return { sx, sy, L, R, T, B,
             ix: (px) => x0 + ((px - L) / (w - L - R)) * (x1 - x0),
             iy: (py) => y0 + ((h - B - py) / (h - T - B)) * (y1 - y0) };
  }
  function ticks(a, b, n) {
    const step = Math.pow(10, Math.floor(Math.log10((b - a) / n)));
    const m = [1, 2, 5, 10].find((k) => (b - a) / (k * step) <= n) * step;
    const out = [];
    for (let t = Math.ceil(a / m) * m; t <= b + 1e-9 * m; t += m) out.push(t);
    return out;
  }
  function fmt(v) { return Math.abs(v) >= 100 || v === 0 ? v.toFixed(0) : Number(v.toPrecision(2)).toString(); }
  function fmt3(v) { return Math.abs(v) >= 1000 ? v.toFixed(0) : Number(v.toPrecision(3)).toString(); }
  function line(ctx, xs, ys, sx, sy, color, width) {
    ctx.strokeStyle = color; ctx.lineWidth = width; ctx.beginPath();
    for (let i = 0; i < xs.length; i++) (i ? ctx.lineTo : ctx.moveTo).call(ctx, sx(xs[i]), sy(ys[i]));
    ctx.stroke();
  }
  function shadeZones(ctx, xs, zone, sx, top, bottom) {
    const dx = xs[1] - xs[0];
    for (let i = 0; i < xs.length; i++) {
      if (!zone[i]) continue;
      ctx.fillStyle = PALETTE[CODED[zone[i] - 1]] + "40";
      ctx.fillRect(sx(xs[i] - dx / 2), top, sx(xs[i] + dx / 2) - sx(xs[i] - dx / 2) + 0.5, bottom - top);
    }
  }
  function kickMarks(ctx, sx, top, bottom) { // the kick-zone marks of the ski, dashed, named
    const kz = META.kick_zone_mm[state.ski];
    if (!kz) return;
    ctx.save(); ctx.strokeStyle = PALETTE.kick_zone; ctx.setLineDash([5, 4]); ctx.lineWidth = 1.5;
    for (const k of kz) { ctx.beginPath(); ctx.moveTo(sx(k), top); ctx.lineTo(sx(k), bottom); ctx.stroke(); }
    ctx.setLineDash([]); ctx.fillStyle = PALETTE.kick_zone; ctx.textAlign = "center";
    ctx.fillText("kick zone", (sx(kz[0]) + sx(kz[1])) / 2, top + 14); ctx.restore();
  }

  function drawProfile(p, xs, zone) {
    const { c, ctx, w, h } = setupCanvas("profile");
    const bottom = curve("base_um", p), snow = curve("snow_um", p);
    const zoom = document.getElementById("zoom").checked;
    let lo = 0, hi = 0;
    for (let i = 0; i < xs.length; i++) { lo = Math.min(lo, snow[i], bottom[i]); hi = Math.max(hi, bottom[i]); }
    if (zoom) hi = Math.min(hi, Math.max(-3 * lo, 100));
    const ax = axes(ctx, w, h, xs[0], xs[xs.length - 1], lo * 1.05 - 1, hi * 1.02 + 1,
      "x from the balance point [mm] (tip →)", "height [µm]");
    shadeZones(ctx, xs, zone, ax.sx, ax.T, h - ax.B);
    ctx.save(); ctx.beginPath(); ctx.rect(ax.L, ax.T, w - ax.L - ax.R, h - ax.T - ax.B); ctx.clip();
    line(ctx, xs, snow, ax.sx, ax.sy, "#5aa0d8", 2);
    line(ctx, xs, bottom, ax.sx, ax.sy, "#222", 1.5);
    kickMarks(ctx, ax.sx, ax.T, h - ax.B);
    const xm = META.grid.load_position_mm[state.pos];
    ctx.fillStyle = "#c00"; ctx.beginPath(); ctx.moveTo(ax.sx(xm), ax.T + 22);
    ctx.lineTo(ax.sx(xm) - 6, ax.T + 10); ctx.lineTo(ax.sx(xm) + 6, ax.T + 10); ctx.fill();
    ctx.restore();
    const kz = META.kick_zone_mm[state.ski];
    c.dataset.kickMarks = kz ? kz.map((k) => ax.sx(k).toFixed(1)).join(",") : "";
  }

  function drawPressure(p, xs, zone) {
    const { ctx, w, h } = setupCanvas("pressure");
    const pr = curve("pressure_kpa", p);
    let hi = 1; for (const v of pr) hi = Math.max(hi, v);
    const ax = axes(ctx, w, h, xs[0], xs[xs.length - 1], 0, hi * 1.08,
      "x from the balance point [mm] (tip →)", "pressure [kPa]");
    shadeZones(ctx, xs, zone, ax.sx, ax.T, h - ax.B);
    kickMarks(ctx, ax.sx, ax.T, h - ax.B);
    line(ctx, xs, pr, ax.sx, ax.sy, "#14365d", 1.5);
  }

  function edges(v) { // cell edges of grid values (midpoints; the outer cells mirrored)
    const n = v.length, e = new Array(n + 1);
    if (n === 1) { const d = Math.max(Math.abs(v[0]) * 0.1, 1); return [v[0] - d, v[0] + d]; }
    for (let i = 1; i < n; i++) e[i] = (v[i - 1] + v[i]) / 2;
    e[0] = v[0] - (v[1] - v[0]) / 2; e[n] = v[n - 1] + (v[n - 1] - v[n - 2]) / 2;
    return e;
  }
  function colour(t) { // the figures' colour map, linear between its stops
    const k = Math.max(0, Math.min(1, t)) * (CMAP.length - 1), i = Math.min(Math.floor(k), CMAP.length - 2), f = k - i;
    const a = CMAP[i], b = CMAP[i + 1], ch = (s, j) => parseInt(s.substr(1 + 2 * j, 2), 16);
    return `rgb(${[0, 1, 2].map((j) => Math.round(ch(a, j) * (1 - f) + ch(b, j) * f)).join(",")})`;
  }
  const MAPS = {};
  function drawMap(id, name, label, unit) {
    const { c, ctx, w, h } = setupCanvas(id, 200);
    const g = META.grid, nm = g.mass_kg.length, ne = g.snow_modulus_mpa.length;
    const em = edges(g.mass_kg), ee = edges(g.snow_modulus_mpa), CB = 74;
    const ax = axes(ctx, w, h, em[0], em[nm], ee[0], ee[ne], "skier mass [kg]", "snow modulus [MPa]",
      { R: CB, xticks: thin(g.mass_kg, (w - 52 - CB) / 36), yticks: thin(g.snow_modulus_mpa, (h - 44) / 16) });
    const tz = zoneIndex("total");
    let lo = Infinity, hi = -Infinity; const vals = [];
    for (let a = 0; a < nm; a++) for (let e = 0; e < ne; e++) {
      const v = metric(name, pointAt(a, e), tz); vals.push(v);
      if (isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    }
    for (let a = 0; a < nm; a++) for (let e = 0; e < ne; e++) {
      const v = vals[a * ne + e];
      ctx.fillStyle = isFinite(v) ? colour((v - lo) / (hi - lo || 1)) : "#ddd";
      const x0 = ax.sx(em[a]), x1 = ax.sx(em[a + 1]), y0 = ax.sy(ee[e + 1]), y1 = ax.sy(ee[e]);
      ctx.fillRect(x0, y0, x1 - x0 + 0.5, y1 - y0 + 0.5);
    }
    // the point shown: the cell of the selected mass and modulus, on their true values
    const mx0 = ax.sx(em[state.mass]), mx1 = ax.sx(em[state.mass + 1]);
    const my0 = ax.sy(ee[state.mod + 1]), my1 = ax.sy(ee[state.mod]);
    ctx.strokeStyle = "#fff"; ctx.lineWidth = 2.5; ctx.strokeRect(mx0, my0, mx1 - mx0, my1 - my0);
    ctx.strokeStyle = "#000"; ctx.lineWidth = 1; ctx.strokeRect(mx0 - 1.5, my0 - 1.5, mx1 - mx0 + 3, my1 - my0 + 3);
    c.dataset.marker = JSON.stringify({ mass: [ax.ix(mx0), ax.ix(mx1)], modulus: [ax.iy(my1), ax.iy(my0)] });
    // the colour bar over the data's range, with numbers
    const bx = w - CB + 12, bw = 14, top = ax.T, bot = h - ax.B;
    for (let y = top; y < bot; y++) { ctx.fillStyle = colour((bot - y) / (bot - top)); ctx.fillRect(bx, y, bw, 1.5); }
    ctx.strokeStyle = "#888"; ctx.strokeRect(bx, top, bw, bot - top);
    ctx.fillStyle = "#333"; ctx.textAlign = "left";
    const lab = [];
    if (isFinite(lo)) {
      const cb = (v) => top + (bot - top) * (1 - (v - lo) / (hi - lo || 1));
      for (const t of ticks(lo, hi, 4)) if (cb(t) > top + 14 && cb(t) < bot - 14) ctx.fillText(fmt(t), bx + bw + 3, cb(t) + 4);
      ctx.fillText(fmt3(hi), bx + bw + 3, top + 9); ctx.fillText(fmt3(lo), bx + bw + 3, bot);
      lab.push(fmt3(lo), fmt3(hi));
    }
    ctx.save(); ctx.translate(w - 6, (top + bot) / 2); ctx.rotate(-Math.PI / 2); ctx.textAlign = "center";
    ctx.fillText(unit, 0, 0); ctx.restore();
    c.dataset.colorbar = lab.join(" ");
    document.getElementById(id + "-label").textContent =
      `${label}: colour from ${lab[0] || "–"} to ${lab[1] || "–"} ${unit} (the data's range); grey = load not carried`;
    MAPS[id] = { ax, em, ee, vals, name, label, unit };
  }
  function thin(values, room) { // at most `room` tick labels, always on grid values
    const k = Math.max(1, Math.ceil(values.length / Math.max(room, 1)));
    return values.filter((_, i) => i % k === 0);
  }
  function cellAt(id, ev) {
    const m = MAPS[id]; if (!m) return null;
    const r = ev.target.getBoundingClientRect(), x = m.ax.ix(ev.clientX - r.left), y = m.ax.iy(ev.clientY - r.top);
    const a = m.em.findIndex((e, i) => i < m.em.length - 1 && x >= e && x < m.em[i + 1]);
    const e = m.ee.findIndex((v, i) => i < m.ee.length - 1 && y >= v && y < m.ee[i + 1]);
    return a < 0 || e < 0 ? null : { a, e };
  }
  function readout(id, cell) {
    const m = MAPS[id], g = META.grid, el = document.getElementById(id + "-readout");
    if (!cell) { el.textContent = ""; return; }
    const v = m.vals[cell.a * g.snow_modulus_mpa.length + cell.e];
    el.textContent = `${g.mass_kg[cell.a]} kg, ${g.snow_modulus_mpa[cell.e]} MPa: ` +
      (isFinite(v) ? `${fmt3(v)} ${m.unit}` : "load not carried");
  }

  function table(p) {
    const rows = ZONE_NAMES.map((z, q) => {
      const cell = (n, d) => { const v = metric(n, p, q); return isFinite(v) ? v.toFixed(d) : "–"; };
      const sw = `<span class="sw" style="background:${PALETTE[z]}"></span>`;
      const head = z === "rear" ? '<tr class="view"><td colspan="7">the paper\'s zones (whole patches; the regions once the patches merge)</td></tr>'
        : z === "rear_glide" ? '<tr class="view"><td colspan="7">regions fixed by the ski</td></tr>' : "";
      return head + `<tr data-zone="${z}"><td>${sw}${LABELS[z] || z}</td><td class="length">${cell("length_mm", 1)}</td>` +
        `<td>${cell("area_cm2", 1)}</td><td>${cell("mean_pressure_kpa", 1)}</td>` +
        `<td>${cell("max_pressure_kpa", 1)}</td><td>${(100 * metric("load_share", p, q)).toFixed(1)}</td>` +
        `<td>${metric("patches", p, q)}</td></tr>`;
    });
    document.getElementById("zones").innerHTML = rows.join("");
    const conv = DATA.converged.v[p], kq = zoneIndex("kick_zone");
    const kick = kq < 0 ? 0 : metric("length_mm", p, kq);
    const g = META.grid;
    document.getElementById("status").textContent =
      `${g.ski[state.ski]}, ${g.model[state.model]} ski (${META.route[g.model[state.model]]} route), ` +
      `${g.mass_kg[state.mass]} kg at ${g.load_position_mm[state.pos]} mm from the balance point, ` +
      `snow ${g.snow_modulus_mpa[state.mod]} MPa: ` + (conv ? "converged" : "NOT converged / load not carried") +
      (kick > 0 ? ` · the kick zone touches the snow over ${kick.toFixed(1)} mm` : "");
  }
  function legend() {
    const sw = (c) => `<span class="sw" style="background:${c}"></span>`;
    document.getElementById("legend").innerHTML = sw("#222") + "ski base" + sw("#5aa0d8") + "snow surface" +
      CODED.map((z) => sw(PALETTE[z] + "66") + LABELS[z]).join("") +
      (META.kick_zone_mm[state.ski] ? sw(PALETTE.kick_zone) + "kick-zone marks (dashed)" : "") + " · ▼ load";
  }

  function labels() {
    const g = META.grid;
    document.getElementById("mass-value").textContent = g.mass_kg[state.mass] + " kg";
    document.getElementById("pos-value").textContent = g.load_position_mm[state.pos] + " mm";
    document.getElementById("mod-value").textContent = g.snow_modulus_mpa[state.mod] + " MPa";
  }

  // ---- the link (URL fragment) and the export of the case shown ------------------------------
  function fragment() {
    const g = META.grid;
    return "#" + new URLSearchParams({ ski: g.ski[state.ski], model: g.model[state.model], base: g.base[state.base],
      mass: g.mass_kg[state.mass], pos: g.load_position_mm[state.pos], mod: g.snow_modulus_mpa[state.mod],
      zoom: document.getElementById("zoom").checked ? "1" : "0" }).toString();
  }
  function restore() { // settings from the URL fragment, each to the nearest grid value
    const q = new URLSearchParams(window.location.hash.slice(1)), g = META.grid;
    const near = (vals, v) => vals.reduce((b, x, i) => (Math.abs(x - v) < Math.abs(vals[b] - v) ? i : b), 0);
    if (q.has("ski") && g.ski.indexOf(q.get("ski")) >= 0) document.getElementById("ski").value = g.ski.indexOf(q.get("ski"));
    if (q.has("model") && g.model.indexOf(q.get("model")) >= 0) document.getElementById("model").value = g.model.indexOf(q.get("model"));
    if (q.has("base") && g.base.indexOf(q.get("base")) >= 0) document.getElementById("base").value = g.base.indexOf(q.get("base"));
    for (const [key, id, vals] of [["mass", "mass", g.mass_kg], ["pos", "pos", g.load_position_mm], ["mod", "mod", g.snow_modulus_mpa]]) {
      if (q.has(key) && isFinite(Number(q.get(key)))) document.getElementById(id).value = near(vals, Number(q.get(key)));
    }
    if (q.has("zoom")) document.getElementById("zoom").checked = q.get("zoom") === "1";
  }
  function shownCase() {
    const g = META.grid, p = point(), xs = DATA["x_mm"].v.subarray(state.ski * META.n_stations, (state.ski + 1) * META.n_stations);
    const zones = {};
    ZONE_NAMES.forEach((z, q) => { zones[z] = {}; for (const n of ["length_mm", "area_cm2", "mean_pressure_kpa", "max_pressure_kpa", "load_share", "patches"]) { const v = metric(n, p, q); zones[z][n] = isFinite(v) ? v : null; } });
    return { ski: g.ski[state.ski], ski_model: g.model[state.model], profile_route: META.route[g.model[state.model]],
      mass_kg: g.mass_kg[state.mass], load_position_mm: g.load_position_mm[state.pos], snow_modulus_mpa: g.snow_modulus_mpa[state.mod],
      kick_zone_mm: META.kick_zone_mm[state.ski], converged: !!DATA.converged.v[p], skisnow_version: META.skisnow_version, zones,
      stations: { x_mm: Array.from(xs), pressure_kpa: Array.from(curve("pressure_kpa", p)), base_um: Array.from(curve("base_um", p)),
        snow_um: Array.from(curve("snow_um", p)), zone: Array.from(row("zone_code", p)).map((k) => (k ? CODED[k - 1] : "")) } };
  }
  function exportText(kind) {
    const c = shownCase();
    if (kind === "json") return JSON.stringify(c, null, 1);
    const head = `# skisnow explorer ${c.skisnow_version}: ${c.ski}, ${c.ski_model} ski (${c.profile_route} route), ${c.mass_kg} kg at ${c.load_position_mm} mm from the balance point, snow ${c.snow_modulus_mpa} MPa`;
    const zl = ["zone,length_mm,area_cm2,mean_pressure_kpa,max_pressure_kpa,load_share,patches"].concat(
      Object.entries(c.zones).map(([z, v]) => [z, v.length_mm, v.area_cm2, v.mean_pressure_kpa, v.max_pressure_kpa, v.load_share, v.patches].map((x) => (x === null ? "" : x)).join(",")));
    const s = c.stations, sl = ["x_mm,pressure_kpa,base_um,snow_um,zone"].concat(s.x_mm.map((x, i) => [x, s.pressure_kpa[i], s.base_um[i], s.snow_um[i], s.zone[i]].join(",")));
    return [head, ...zl, "", ...sl].join("\n") + "\n";
  }
  function download(kind) {
    const text = exportText(kind), a = document.createElement("a");
    a.href = URL.createObjectURL(new Blob([text], { type: kind === "json" ? "application/json" : "text/csv" }));
    a.download = `skisnow-${META.grid.ski[state.ski]}-${META.grid.mass_kg[state.mass]}kg.${kind}`;
    document.body.appendChild(a); a.click(); a.remove();
  }

  function render() {
    labels(); legend();
    const p = point(), xs = DATA["x_mm"].v.subarray(state.ski * META.n_stations, (state.ski + 1) * META.n_stations);
    const zone = row("zone_code", p);
    drawProfile(p, xs, zone); drawPressure(p, xs, zone); table(p);
    if (META.real) drawReal(p, xs, zone);
    drawMap("map-area", "area_cm2", "total contact area", "cm²");
    drawMap("map-pressure", "mean_pressure_kpa", "mean pressure (total)", "kPa");
    document.body.dataset.point = String(p);
    const f = fragment();
    document.getElementById("link").href = f;
    if (window.location.hash !== f) history.replaceState(null, "", f);
  }

  function bind(id, key) {
    const el = document.getElementById(id);
    const update = () => { state[key] = Number(el.value); render(); };
    el.addEventListener("input", update);
    el.addEventListener("change", update);
    state[key] = Number(el.value);
  }
  function bindMap(id) {
    const c = document.getElementById(id);
    c.addEventListener("mousemove", (ev) => readout(id, cellAt(id, ev)));
    c.addEventListener("mouseleave", () => readout(id, null));
    c.addEventListener("click", (ev) => { // a tap selects the grid point and shows its value
      const cell = cellAt(id, ev); if (!cell) return;
      document.getElementById("mass").value = cell.a; document.getElementById("mod").value = cell.e;
      state.mass = cell.a; state.mod = cell.e; render(); readout(id, cell);
    });
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
    const baseSel = document.getElementById("base");
    g.ski.forEach((s, i) => skiSel.add(new Option(s, i)));
    g.model.forEach((s, i) => modelSel.add(new Option(s, i)));
    g.base.forEach((s, i) => baseSel.add(new Option(s || "(none)", i)));
    modelSel.disabled = g.model.length < 2;
    baseSel.disabled = g.base.length < 2;
    document.getElementById("base-label").hidden = !META.real;
    document.getElementById("real-panel").hidden = !META.real;
    restore();
    bind("mass", "mass"); bind("pos", "pos"); bind("mod", "mod"); bind("ski", "ski"); bind("model", "model");
    bind("base", "base");
    document.getElementById("zoom").addEventListener("change", render);
    bindMap("map-area"); bindMap("map-pressure");
    document.getElementById("export-csv").addEventListener("click", () => download("csv"));
    document.getElementById("export-json").addEventListener("click", () => download("json"));
    DATA = await decode();
    window.skisnowExplorer = { exportText, state };
    window.addEventListener("resize", render);
    render();
    document.body.dataset.ready = "1";
  }
  main().catch((e) => { document.getElementById("status").textContent = "error: " + e; throw e; });
})();
