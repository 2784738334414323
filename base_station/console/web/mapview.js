// Cairn console, the map view: Leaflet (served by the base from npm; no CDN in the field) in a
// simple metric CRS, one map unit per metre, x east (longitude) and y north (latitude). The merged
// occupancy grid comes as tiles (/api/tiles, revalidated by ETag so a tile that did not change costs
// a 304); the rest are switchable vector layers drawn from the JSON API.
"use strict";

const MapView = (() => {
  // The exporter's robot palette (exporter_image.cpp), so the map view and map.png agree.
  const ROBOT_COLOURS = ["#145ac8", "#1e8c1e", "#a02896", "#c87814", "#007878", "#8c3c5a"];
  const CLASS_STYLE = {
    victim: { colour: "#dc1e1e", letter: "V" }, hazard: { colour: "#ff8c00", letter: "H" },
    exit: { colour: "#28a028", letter: "E" },
  };
  let map = null;
  let tiles = null;
  const live = new Map();  // tile key -> {img, etag}: the tiles shown, refetched when the map changes
  const layers = {};
  // The view follows the growing map (fitted to its known part) until the operator pans or zooms;
  // the "whole map" button fits it again and follows once more.
  let follow = true;
  let fitting = false;
  let lastBounds = null;
  let handlers = { mapClick() {}, robotClick() {} };

  const robotColour = (id) => ROBOT_COLOURS[Math.abs(id) % ROBOT_COLOURS.length];
  const ll = (x, y) => L.latLng(y, x);

  async function loadTile(key, url, entry) {
    // cache "no-cache": the browser revalidates with If-None-Match; a 304 reaches us as the cached 200.
    const res = await fetch(url, { cache: "no-cache" });
    if (!res.ok) throw new Error(`tile ${key}: HTTP ${res.status}`);
    const etag = res.headers.get("ETag");
    if (etag && etag === entry.etag) return;  // unchanged: keep the pixels shown
    const src = URL.createObjectURL(await res.blob());
    await new Promise((ok) => { entry.img.onload = ok; entry.img.onerror = ok; entry.img.src = src; });
    if (entry.src) URL.revokeObjectURL(entry.src);
    entry.src = src;
    entry.etag = etag;
  }

  const GridTiles = L.GridLayer.extend({
    createTile(coords, done) {
      const img = document.createElement("img");
      img.alt = "";
      const key = `${coords.z}/${coords.x}/${coords.y}`;
      const entry = { img, etag: null, src: null, url: `/api/tiles/${key}.png` };
      live.set(key, entry);
      loadTile(key, entry.url, entry).then(() => done(null, img), (e) => done(e, img));
      return img;
    },
  });

  // Metre grid lines, spaced so that they stay at least ~60 px apart. Written here: Leaflet has no
  // metric graticule for a simple CRS, and a canvas per tile is a few lines.
  const MetreGrid = L.GridLayer.extend({
    createTile(coords) {
      const canvas = document.createElement("canvas");
      const size = this.getTileSize();
      canvas.width = size.x;
      canvas.height = size.y;
      const pxPerM = Math.pow(2, coords.z);
      const step = [1, 2, 5, 10, 20, 50, 100, 200, 500].find((s) => s * pxPerM >= 60) || 1000;
      const ctx = canvas.getContext("2d");
      ctx.strokeStyle = "rgba(40, 90, 160, 0.25)";
      ctx.lineWidth = 1;
      const x0 = (coords.x * size.x) / pxPerM, y0 = (coords.y * size.y) / pxPerM;  // metres (y down)
      for (let m = Math.ceil(x0 / step) * step; m * pxPerM < (coords.x + 1) * size.x; m += step) {
        const u = Math.round(m * pxPerM - coords.x * size.x) + 0.5;
        ctx.beginPath(); ctx.moveTo(u, 0); ctx.lineTo(u, size.y); ctx.stroke();
      }
      for (let m = Math.ceil(y0 / step) * step; m * pxPerM < (coords.y + 1) * size.y; m += step) {
        const v = Math.round(m * pxPerM - coords.y * size.y) + 0.5;
        ctx.beginPath(); ctx.moveTo(0, v); ctx.lineTo(size.x, v); ctx.stroke();
      }
      return canvas;
    },
  });

  function init(h) {
    handlers = { ...handlers, ...h };
    const box = document.getElementById("map");
    if (!window.L) {
      box.textContent = "The map library (Leaflet) is not installed: run scripts/install_deps.sh on the base.";
      box.classList.add("missing");
      return;
    }
    map = L.map(box, { crs: L.CRS.Simple, minZoom: -4, maxZoom: 8, zoomSnap: 0.25, attributionControl: false });
    map.setView([0, 0], 3);
    tiles = new GridTiles({ minNativeZoom: -4, maxNativeZoom: 6, tileSize: 256, className: "occupancy-tiles" }).addTo(map);
    tiles.on("tileunload", (e) => {
      for (const [key, entry] of live) if (entry.img === e.tile) {
        if (entry.src) URL.revokeObjectURL(entry.src);
        live.delete(key);
      }
    });
    const canvas = L.canvas({ padding: 0.2 });
    const group = (name, shown) => {
      layers[name] = L.layerGroup();
      if (shown) layers[name].addTo(map);
      return layers[name];
    };
    const overlays = {
      "Metre grid": new MetreGrid({ tileSize: 256, pane: "overlayPane" }).addTo(map),
      "Saliency": group("saliency", true),
      "Frontiers": group("frontiers", true),
      "Trajectories": group("trajectories", true),
      "Goals": group("goals", true),
      "Planned paths": group("paths", true),
      "Could not reach": group("unreachable", true),
      "Objects": group("objects", true),
      "Robots": group("robots", true),
      "Keep-out areas": group("keepOut", true),
    };
    layers.canvas = canvas;
    L.control.layers(null, overlays, { position: "topright" }).addTo(map);
    L.control.scale({ imperial: false, maxWidth: 150 }).addTo(map);
    map.on("click", (e) => handlers.mapClick(e.latlng.lng, e.latlng.lat));
    map.on("movestart zoomstart", () => { if (!fitting) follow = false; });
    const WholeMap = L.Control.extend({
      onAdd() {
        const b = L.DomUtil.create("button", "whole-map");
        b.textContent = "Whole map";
        b.title = "Fit the whole map and follow it as it grows";
        L.DomEvent.disableClickPropagation(b);
        b.addEventListener("click", () => { follow = true; fit(lastBounds); });
        return b;
      },
    });
    new WholeMap({ position: "topleft" }).addTo(map);
  }

  // The map changed at the base: refetch the tiles shown (unchanged ones cost a 304), at most once a
  // second (the robots and objects above them update at every change).
  let lastTileRefresh = 0;
  let tileTimer = null;
  function refreshTiles() {
    if (!map) return;
    const wait = 1000 - (Date.now() - lastTileRefresh);
    if (wait > 0) {
      if (!tileTimer) tileTimer = setTimeout(() => { tileTimer = null; refreshTiles(); }, wait);
      return;
    }
    lastTileRefresh = Date.now();
    for (const [key, entry] of live) {
      if (!entry.img.isConnected) continue;
      loadTile(key, entry.url, entry).catch(() => {});
    }
  }

  function fit(bounds) {
    if (!map || !bounds) return;
    fitting = true;
    map.fitBounds(L.latLngBounds(ll(bounds[0][0], bounds[0][1]), ll(bounds[1][0], bounds[1][1])), { padding: [10, 10], animate: false });
    fitting = false;
  }

  // Refit only when the map outgrew the view or fills less than a quarter of it, and never while
  // the operator is placing a point (a robot selected, a keep-out area being drawn, a robot's map
  // being aligned): the map must not move under the pointer.
  function followMap(bounds) {
    if (!bounds) return;
    lastBounds = bounds;
    const box = L.latLngBounds(ll(bounds[0][0], bounds[0][1]), ll(bounds[1][0], bounds[1][1]));
    const view = map.getBounds();
    const area = (b) => (b.getEast() - b.getWest()) * (b.getNorth() - b.getSouth());
    const misfit = !view.contains(box) || area(box) < 0.25 * area(view);
    if (follow && misfit && !Control.claimsMapClick() && Align.aligning() === null) fit(bounds);
  }

  function drawTrajectories(robots) {
    layers.trajectories.clearLayers();
    for (const r of robots) {
      if (!r.linked || !r.trajectory || r.trajectory.length < 2) continue;
      L.polyline(r.trajectory.map(([x, y]) => ll(x, y)), { color: robotColour(r.id), weight: 2, interactive: false })
        .addTo(layers.trajectories);
    }
  }

  // The robots' markers are kept and moved, not drawn anew at every update: a marker replaced
  // under the pointer swallows the operator's click (seen in the browser test under load).
  const robotMarkers = new Map();  // robot id -> Leaflet marker
  function drawRobots(robots, selected) {
    const shown = new Set();
    for (const r of robots) {
      if (!r.pose_m) continue;
      const [x, y, yaw] = r.pose_m;
      shown.add(r.id);
      let marker = robotMarkers.get(r.id);
      if (!marker) {
        const icon = L.divIcon({ className: "", iconSize: [26, 26], iconAnchor: [13, 13],
          html: `<button class="robot-marker">${r.id}</button>` });
        marker = L.marker(ll(x, y), { icon, keyboard: false, zIndexOffset: 1000 })
          .on("click", (e) => { L.DomEvent.stopPropagation(e); handlers.robotClick(r.id); })
          .addTo(layers.robots);
        robotMarkers.set(r.id, marker);
      }
      marker.setLatLng(ll(x, y));
      const button = marker.getElement() && marker.getElement().querySelector("button");
      if (!button) continue;
      button.classList.toggle("selected", r.id === selected);
      button.style.setProperty("--yaw", `${-yaw}rad`);
      button.style.setProperty("--colour", robotColour(r.id));
      button.title = `Robot ${r.id}: ${(r.link && r.link.activity) || "?"}`;
    }
    for (const [id, marker] of robotMarkers) {
      if (shown.has(id)) continue;
      layers.robots.removeLayer(marker);
      robotMarkers.delete(id);
    }
  }

  // Each robot's next goal (the plan's, dashed; a meeting with a teammate, dotted to a filled dot)
  // and the point the operator sent it to (ringed);
  // the path its own planner drives there (solid, from where it is: what it reported last).
  function drawGoals(robots, exploration, commands) {
    layers.goals.clearLayers();
    layers.paths.clearLayers();
    for (const r of robots) {
      if (!r.pose_m || !r.path_m || r.path_m.length < 2) continue;
      const points = [ll(r.pose_m[0], r.pose_m[1]), ...r.path_m.slice(1).map(([x, y]) => ll(x, y))];
      L.polyline(points, { color: robotColour(r.id), weight: 3, opacity: 0.75, interactive: false, className: "planned-path" })
        .addTo(layers.paths);
    }
    const pose = new Map(robots.filter((r) => r.pose_m).map((r) => [r.id, r.pose_m]));
    for (const g of (exploration && exploration.goals) || []) {
      const from = pose.get(g.robot);
      const colour = robotColour(g.robot);
      if (from) L.polyline([ll(from[0], from[1]), ll(g.x_m, g.y_m)], { color: colour, weight: 2, dashArray: "6 6", interactive: false }).addTo(layers.goals);
      L.circleMarker(ll(g.x_m, g.y_m), { radius: 6, color: colour, weight: 2, fill: false, interactive: false }).addTo(layers.goals);
    }
    for (const m of (exploration && exploration.meetings) || []) {  // active linking: toward a teammate
      const from = pose.get(m.robot);
      const colour = robotColour(m.robot);
      if (from) L.polyline([ll(from[0], from[1]), ll(m.x_m, m.y_m)], { color: colour, weight: 2, dashArray: "2 6", interactive: false }).addTo(layers.goals);
      L.circleMarker(ll(m.x_m, m.y_m), { radius: 4, color: colour, weight: 2, fill: true, fillOpacity: 0.6, interactive: false })
        .addTo(layers.goals);
    }
    const latest = new Map();
    for (const c of commands) if (!latest.has(c.robot)) latest.set(c.robot, c);  // newest first
    for (const c of latest.values()) {
      if (c.kind !== "goto" || !["sent", "received", "active", "done"].includes(c.state)) continue;
      L.marker(ll(c.x_m, c.y_m), {
        interactive: false, keyboard: false,
        icon: L.divIcon({ className: "", iconSize: [22, 22], iconAnchor: [11, 11],
          html: `<div class="operator-target" title="Robot ${c.robot}: the operator's point (command ${c.seq}, ${c.state})">${c.robot}</div>` }),
      }).addTo(layers.goals);
    }
  }

  function drawObjects(objects) {
    layers.objects.clearLayers();
    for (const o of objects) {
      if (o.frame && o.frame !== "global") continue;  // not on the map yet: listed with where it is
      const [x, y] = o.position_m;
      const style = CLASS_STYLE[o.class] || { colour: "#3c3cb4", letter: "?" };
      const sigma = Math.max(o.sigma_m ? Math.hypot(o.sigma_m[0], o.sigma_m[1]) : 0, 0.05);
      L.circle(ll(x, y), { radius: 2 * sigma, color: style.colour, weight: 1, fillOpacity: 0.1, interactive: false })
        .addTo(layers.objects);
      const popup = `<b>${o.class} ${o.id}</b> · ${Math.round(100 * o.confidence)} %<br>` +
        `(${x.toFixed(2)}, ${y.toFixed(2)}, ${o.position_m[2].toFixed(2)}) m ± ${sigma.toFixed(2)} m<br>` +
        `seen by ${(o.robots || []).map((r) => `robot ${r}`).join(", ")} · ${o.verdict || "unreviewed"}` +
        (o.thumbnail ? `<br><img class="popup-thumb" src="${o.thumbnail}" alt="">` : "");
      L.marker(ll(x, y), {
        keyboard: false,
        icon: L.divIcon({ className: "", iconSize: [22, 22], iconAnchor: [11, 11],
          html: `<div class="object-marker ${o.verdict || ""}" style="background:${style.colour}">${style.letter}</div>` }),
      }).bindPopup(popup).addTo(layers.objects);
    }
  }

  function drawPlanLayers(l) {
    layers.frontiers.clearLayers();
    layers.saliency.clearLayers();
    layers.unreachable.clearLayers();
    for (const f of l.frontiers || []) {
      L.circleMarker(ll(f.x_m, f.y_m), { renderer: layers.canvas, radius: Math.min(10, 3 + f.length_m), color: "#0a8ca0",
        weight: 2, fillOpacity: 0.3, interactive: false }).addTo(layers.frontiers);
    }
    const s = l.saliency || {};
    const h = (s.cell_m || 0) / 2;
    for (const [x, y, v] of s.cells || []) {
      L.rectangle([ll(x - h, y - h), ll(x + h, y + h)], { renderer: layers.canvas, stroke: false, fillColor: "#ff9600",
        fillOpacity: 0.6 * v, interactive: false }).addTo(layers.saliency);
    }
    for (const u of l.unreachable || []) {
      L.marker(ll(u.x_m, u.y_m), { interactive: false, keyboard: false,
        icon: L.divIcon({ className: "", iconSize: [14, 14], iconAnchor: [7, 7],
          html: `<div class="unreachable-marker" title="Robot ${u.robot} could not reach this point (${u.why})">×</div>` }),
      }).addTo(layers.unreachable);
    }
  }

  // The operator's keep-out areas: hatched red, each with a "Remove" in its popup.
  function drawKeepOut(search) {
    layers.keepOut.clearLayers();
    for (const a of (search && search.keep_out) || []) {
      const box = L.rectangle([ll(a.min_m[0], a.min_m[1]), ll(a.max_m[0], a.max_m[1])],
        { color: "#c00", weight: 2, dashArray: "4 4", fillColor: "#c00", fillOpacity: 0.15, className: "keep-out" });
      const body = el("div", {}, [document.createTextNode(`Keep-out area ${a.id}: no robot is sent in or through it`)]);
      if (Control.canCommand()) {
        const remove = el("button", { class: "remove-keep-out", text: "Remove" });
        remove.addEventListener("click", () => Control.removeKeepOut(a.id));
        body.appendChild(el("div", {}, [remove]));
      }
      // A click inside goes to the map when the operator is placing a point (a goto there is then
      // refused with the reason); otherwise it opens the area's popup.
      box.on("click", (e) => {
        L.DomEvent.stop(e);
        if (Control.claimsMapClick()) handlers.mapClick(e.latlng.lng, e.latlng.lat);
        else L.popup().setLatLng(e.latlng).setContent(body).openOn(map);
      }).addTo(layers.keepOut);
    }
  }

  return {
    init,
    refreshTiles,
    leaflet: () => map,
    robotColour,
    /// Everything but the tiles, from the API's JSON.
    update({ robots, objects, exploration, layers: planLayers, commands, selected, search }) {
      if (!map) return;
      followMap(planLayers && planLayers.bounds_m);
      drawPlanLayers(planLayers || {});
      drawTrajectories(robots);
      drawGoals(robots, exploration, commands);
      drawObjects(objects);
      drawRobots(robots, selected);
      drawKeepOut(search);
    },
    /// Where map point (x_m, y_m) is in the map's box, in CSS px from its top-left corner (tests).
    pixelOf(x_m, y_m) {
      if (!map) return null;
      const p = map.latLngToContainerPoint(ll(x_m, y_m));
      return { x: p.x, y: p.y };
    },
  };
})();
