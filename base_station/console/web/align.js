// Cairn console: the operator aligns a robot the base has not placed yet. Its own map (its walls
// and path in its own frame, /api/layers "own_frames") is drawn over the global map where the
// operator puts it: drag the round handle (where it entered) to move it, the arrow handle to turn
// it. "Ask the base to verify" sends the placement (POST /api/robots/<id>/align); the base looks
// for verified scan matches around it and runs its map check, and the robot's panel shows the
// verdict: placed (and how far the base refined the placement) or refused, and why.
// Written here rather than with a plugin: Leaflet has no rotatable overlay, and moving a few
// thousand points with two draggable markers is a few lines.
"use strict";

const Align = (() => {
  const HANDLE_M = 3;  // the heading handle sits this far from the entry, along the robot's own x
  let map = null;
  let outlineLayer = null;
  let renderer = null;
  let current = null;  // {robot, x, y, yaw, outline, colour, entry, heading}
  let frame = 0;

  function init(leafletMap) {
    map = leafletMap;
    if (!map) return;
    renderer = L.canvas({ padding: 0.2 });
    outlineLayer = L.layerGroup().addTo(map);
  }

  // A point of the robot's own frame on the global map, as placed now.
  function onMap(p) {
    const c = Math.cos(current.yaw), s = Math.sin(current.yaw);
    return L.latLng(current.y + s * p[0] + c * p[1], current.x + c * p[0] - s * p[1]);
  }

  function draw() {
    frame = 0;
    outlineLayer.clearLayers();
    for (const p of current.outline.walls_m || []) {
      L.circleMarker(onMap(p), { renderer, radius: 1.5, stroke: false, fillColor: current.colour, fillOpacity: 0.9,
        interactive: false }).addTo(outlineLayer);
    }
    L.polyline((current.outline.path_m || []).map(onMap), { color: current.colour, weight: 2, dashArray: "4 4",
      interactive: false }).addTo(outlineLayer);
    current.entry.setLatLng(L.latLng(current.y, current.x));
    current.heading.setLatLng(onMap([HANDLE_M, 0]));
    const readout = document.querySelector(`.align-readout[data-robot="${current.robot}"]`);
    if (readout) readout.textContent = describe(current);
  }
  // Dragging fires faster than the page can redraw thousands of points: once per frame.
  function redraw() {
    if (!frame) frame = requestAnimationFrame(draw);
  }

  function describe(p) {
    return `entry at (${p.x.toFixed(2)}, ${p.y.toFixed(2)}) m, heading ${(p.yaw * 180 / Math.PI).toFixed(1)} deg`;
  }

  function handle(cls, symbol) {
    return L.marker([0, 0], { draggable: true, autoPan: true, zIndexOffset: 1000,
      icon: L.divIcon({ className: `align-handle ${cls}`, html: symbol, iconSize: [26, 26] }) });
  }

  /// Starts aligning `robot` (its own map's outline); the map starts at `start` ({x_m, y_m,
  /// yaw_deg}: the last alignment) or the middle of the view, unturned.
  function start(robot, outline, colour, start) {
    if (!map) return;
    stop();
    map.getContainer().scrollIntoView({ block: "center" });  // the button is below the map
    const centre = map.getCenter();
    current = { robot, outline, colour,
      x: start ? start.x_m : centre.lng, y: start ? start.y_m : centre.lat,
      yaw: start ? start.yaw_deg * Math.PI / 180 : 0,
      entry: handle("entry", "✥"), heading: handle("heading", "↻") };
    current.entry.on("drag", (e) => {
      current.x = e.latlng.lng;
      current.y = e.latlng.lat;
      redraw();
    }).addTo(map);
    current.heading.on("drag", (e) => {
      current.yaw = Math.atan2(e.latlng.lat - current.y, e.latlng.lng - current.x);
      redraw();
    }).addTo(map);
    draw();
  }

  function stop() {
    if (!current) return;
    current.entry.remove();
    current.heading.remove();
    outlineLayer.clearLayers();
    current = null;
  }

  /// Sends the placement shown; `done(ok, text)` gets what to tell the operator.
  async function verify(done) {
    if (!current) return;
    const body = { x_m: current.x, y_m: current.y, yaw_deg: current.yaw * 180 / Math.PI };
    const { status, reply } = await Control.post(`/api/robots/${current.robot}/align`, body);
    if (status === 202) {
      done(true, `Sent: ${describe(current)}. The base is verifying it…`);
      stop();
    } else {
      done(false, `Refused: ${reply.error || "the base station is unreachable"}`);
    }
  }

  return {
    init,
    start,
    stop,
    verify,
    aligning: () => (current ? current.robot : null),
    /// The placement shown, in words ("" when not aligning): the panel's readout starts with it,
    /// so a refresh of the panel mid-alignment never shows it blank.
    readout: () => (current ? describe(current) : ""),
    /// The outline's new points while aligning (the robot's map grew).
    update(outlines) {
      if (current && outlines && outlines[current.robot]) {
        current.outline = outlines[current.robot];
        redraw();
      }
    },
  };
})();
