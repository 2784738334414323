// Cairn console, an object's coloured cloud in 3D: three.js (npm, served by the base) with orbit
// controls, in a dialog opened from the objects list or the object's popup on the map. The cloud
// comes from /api/objects/<id>/cloud ([[x, y, z, r, g, b], ...] in the map frame, z up), centred
// on its mean, over a 10 cm floor grid so its size reads at a glance.
import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";

let renderer = null;
let controls = null;
let scene = null;
let camera = null;

function render() { if (renderer) renderer.render(scene, camera); }

function setUp(canvas) {
  renderer = new THREE.WebGLRenderer({ canvas, antialias: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  camera = new THREE.PerspectiveCamera(50, 1, 0.01, 100);
  camera.up.set(0, 0, 1);
  controls = new OrbitControls(camera, canvas);
  controls.addEventListener("change", render);
}

async function show(id, title) {
  const dialog = document.getElementById("cloud-dialog");
  const canvas = document.getElementById("cloud-canvas");
  document.getElementById("cloud-title").textContent = title;
  const note = document.getElementById("cloud-note");
  dialog.showModal();
  if (!renderer) setUp(canvas);
  const width = canvas.clientWidth, height = canvas.clientHeight;
  renderer.setSize(width, height, false);
  camera.aspect = width / height;
  camera.updateProjectionMatrix();
  const points = await fetch(`/api/objects/${id}/cloud`).then((r) => r.json()).catch(() => []);
  note.textContent = points.length ? `${points.length} points · drag to turn, wheel to zoom` : "No points for this object.";
  scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f4f0);
  if (!points.length) return render();
  const mean = [0, 0, 0];
  for (const p of points) for (let k = 0; k < 3; ++k) mean[k] += p[k] / points.length;
  const positions = new Float32Array(points.length * 3), colours = new Float32Array(points.length * 3);
  let radius = 0.1;
  points.forEach((p, i) => {
    for (let k = 0; k < 3; ++k) {
      positions[3 * i + k] = p[k] - (k < 2 ? mean[k] : 0);  // z stays height above the floor
      colours[3 * i + k] = p[3 + k] / 255;
    }
    radius = Math.max(radius, Math.hypot(p[0] - mean[0], p[1] - mean[1], p[2] - mean[2]));
  });
  const geometry = new THREE.BufferGeometry();
  geometry.setAttribute("position", new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute("color", new THREE.BufferAttribute(colours, 3));
  scene.add(new THREE.Points(geometry, new THREE.PointsMaterial({ size: 0.025, vertexColors: true })));
  const floor = new THREE.GridHelper(2, 20, 0x888888, 0xcccccc);
  floor.rotation.x = Math.PI / 2;  // the XY plane: z is up
  scene.add(floor, new THREE.AxesHelper(0.3));
  camera.position.set(1.6 * radius, -1.6 * radius, mean[2] + 1.1 * radius);
  controls.target.set(0, 0, mean[2]);
  controls.update();
  render();
}

document.getElementById("cloud-close").addEventListener("click", () => document.getElementById("cloud-dialog").close());
window.Cloud3D = { show };
