// The report's 3D view of the order (docs/evaluation.md, "The report"): the order played as glTF
// (report/src/gltf.cpp) inlined with three.js, so that the page stays one file that opens from disk.
#include "view3d.hpp"

#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "picture.hpp"
#include "vaw/report/gltf.hpp"

namespace vaw::report {

namespace {

std::string readAll(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) return {};
  std::ostringstream all;
  all << in.rdbuf();
  return std::move(all).str();
}

// A script's text safe inside <script>: no "</" that would end the element early.
std::string scriptText(std::string s) {
  for (std::size_t at = 0; (at = s.find("</", at)) != std::string::npos; at += 3) s.replace(at, 2, "<\\/");
  return s;
}

// Plays, steps, explodes and picks (three.js r111: THREE.GLTFLoader and THREE.OrbitControls as classic
// scripts). A step k shows the base and the parts up to the k-th in place, that step's part highlighted.
// For whoever checks the page (its test): "#step=K&select=NAME&exploded" in the address does what the
// slider, a click and the box do, and body[data-view] holds what the view shows.
constexpr const char* kViewScript = R"JS(
// Started once the page is parsed: the tables it marks and listens to come after the view.
addEventListener('DOMContentLoaded', function () {
  const data = JSON.parse(document.getElementById('view3d-data').textContent);
  const canvas = document.getElementById('view3d-canvas');
  const slider = document.getElementById('view3d-step');
  const label = document.getElementById('view3d-label');
  const play = document.getElementById('view3d-play');
  const exploded = document.getElementById('view3d-exploded');
  const background = 0xf4f6f8;
  const say = (o) => { document.body.dataset.view = JSON.stringify(o); };
  let renderer;
  try {
    renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true, preserveDrawingBuffer: true});
  } catch (e) {
    document.getElementById('view3d').textContent = 'This browser cannot draw the 3D view (no WebGL): ' + e.message;
    say({error: String(e.message)});
    return;
  }
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(background);
  scene.add(new THREE.HemisphereLight(0xffffff, 0x8a9099, 0.85));
  const sun = new THREE.DirectionalLight(0xffffff, 0.75);
  sun.position.set(1, 2, 1.5);
  scene.add(sun);
  const camera = new THREE.PerspectiveCamera(35, 1, 0.001, 1000);
  const controls = new THREE.OrbitControls(camera, canvas);
  const bytes = Uint8Array.from(atob(document.getElementById('view3d-glb').textContent.trim()), (c) => c.charCodeAt(0));
  const parts = {};      // by the part's name: its node
  const apart = {};      // by the part's name: the group between the root and its node that explodes it
  let mixer = null, action = null, root = null, step = data.steps.length - 1, time = 0, playing = false, selected = null, last = 0;
  const centre = new THREE.Vector3();

  function timeOfStep(k) { return (k + 0.9) * data.stepSeconds; }
  function paint() {
    for (const name in parts)
      parts[name].traverse((o) => {
        if (!o.isMesh) return;
        const lit = name === selected ? 0x1f5fbf : name === data.steps[step] ? 0xff8c1a : 0x000000;
        o.material.emissive.setHex(lit);
        o.material.emissiveIntensity = lit ? 0.45 : 0;
      });
    document.querySelectorAll('table#parts tr, table#summary tr').forEach((tr) => {
      const cells = tr.querySelectorAll('td');
      const on = selected !== null && Array.from(cells).some((td) => td.textContent === selected);
      tr.classList.toggle('sel', on);
    });
  }
  function pose(t) {
    time = t;
    if (mixer) {
      action.reset();  // a finished action stays paused at its end: set going again from the start
      mixer.setTime(t);
    }
    // Exploded: each part where its way in starts. Set on a group of its own (in vaw's world frame, under the
    // root's turn): the mixer writes a node only when its value changes, so the node itself is its alone.
    for (const name in apart)
      if (exploded.checked && data.away[name]) apart[name].position.fromArray(data.away[name]);
      else apart[name].position.set(0, 0, 0);
  }
  function show(k) {
    step = Math.max(0, Math.min(data.steps.length - 1, k));
    slider.value = step;
    label.textContent = (step + 1) + ' of ' + data.steps.length + ': ' + data.steps[step];
    pose(timeOfStep(step));
    paint();
  }
  function select(name) {
    selected = name in parts ? name : null;
    paint();
  }
  // The camera on what is shown, looking along `from` (towards the target), at a distance that holds it.
  function frame3d(from) {
    const box = new THREE.Box3();
    if (root) root.updateMatrixWorld(true);
    for (const name in parts) if (parts[name].scale.x > 0) box.expandByObject(parts[name]);
    if (box.isEmpty()) return;
    box.getCenter(centre);
    const size = box.getSize(new THREE.Vector3()).length();
    camera.near = size / 1000;
    camera.far = size * 50;
    camera.position.copy(centre).add(from.clone().normalize().multiplyScalar(1.45 * size));
    camera.updateProjectionMatrix();
    controls.target.copy(centre);
    controls.update();
  }
  function drawn() {
    const gl = renderer.getContext();
    const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
    const px = new Uint8Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    let n = 0;
    for (let i = 0; i < px.length; i += 4)
      if (Math.abs(px[i] - 0xf4) + Math.abs(px[i + 1] - 0xf6) + Math.abs(px[i + 2] - 0xf8) > 24) ++n;
    return n / (w * h);
  }
  function frame(now) {
    const w = canvas.clientWidth, h = canvas.clientHeight;
    if (canvas.width !== Math.floor(w * renderer.getPixelRatio()) || canvas.height !== Math.floor(h * renderer.getPixelRatio())) {
      renderer.setSize(w, h, false);
      camera.aspect = w / h;
      camera.updateProjectionMatrix();
    }
    if (playing) {
      const t = time + Math.min(0.1, (now - last) / 1000);
      const end = data.steps.length * data.stepSeconds;
      if (t >= end) {
        playing = false;
        play.textContent = 'Play';
        show(data.steps.length - 1);
      } else {
        const k = Math.floor(t / data.stepSeconds);
        if (k !== step) {
          step = k;
          slider.value = k;
          label.textContent = (k + 1) + ' of ' + data.steps.length + ': ' + data.steps[k];
          paint();
        }
        pose(t);
      }
    }
    last = now;
    controls.update();
    renderer.render(scene, camera);
    requestAnimationFrame(frame);
  }

  new THREE.GLTFLoader().parse(bytes.buffer, '', (gltf) => {
    scene.add(gltf.scene);
    root = gltf.scene.children[0];
    for (const n of root.children.slice()) {
      const name = n.userData.name || n.name;
      if (n.userData.environment) continue;  // the table: drawn, not framed, exploded or picked
      parts[name] = n;
      apart[name] = new THREE.Group();
      root.add(apart[name]);
      apart[name].add(n);
      n.traverse((o) => { if (o.isMesh) { o.material = o.material.clone(); o.userData.part = name; } });
    }
    if (gltf.animations.length > 0) {
      mixer = new THREE.AnimationMixer(gltf.scene);
      // Once, held at its end: a step's time past the last key shows the end, not the start again.
      action = mixer.clipAction(gltf.animations[0]);
      action.setLoop(THREE.LoopOnce);
      action.clampWhenFinished = true;
      action.play();
    }
    // Framed on the whole assembly (exploded, if asked), whatever step is shown.
    const asked = new URLSearchParams(location.hash.slice(1));
    exploded.checked = asked.has('exploded');
    pose(timeOfStep(data.steps.length - 1));
    frame3d(new THREE.Vector3(0.75, 0.55, 0.95));
    show(asked.has('step') ? parseInt(asked.get('step'), 10) : data.steps.length - 1);
    if (asked.has('select')) select(asked.get('select'));
    requestAnimationFrame((now) => {
      last = now;
      frame(now);
      let shown = 0;
      for (const name in parts) if (parts[name].scale.x > 0) ++shown;
      say({step: step, shown: shown, selected: selected, exploded: exploded.checked, drawn: drawn(), parts: Object.keys(parts).length});
    });
  }, (e) => say({error: String(e)}));

  slider.addEventListener('input', () => { playing = false; play.textContent = 'Play'; show(parseInt(slider.value, 10)); });
  play.addEventListener('click', () => {
    playing = !playing;
    play.textContent = playing ? 'Pause' : 'Play';
    if (playing && step >= data.steps.length - 1) pose(0);
    else if (playing) pose(step * data.stepSeconds);
  });
  exploded.addEventListener('change', () => {
    pose(time);
    frame3d(camera.position.clone().sub(controls.target));
  });
  let down = null;
  canvas.addEventListener('pointerdown', (e) => { down = [e.clientX, e.clientY]; });
  canvas.addEventListener('pointerup', (e) => {
    if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
    const r = canvas.getBoundingClientRect();
    const ray = new THREE.Raycaster();
    ray.setFromCamera(new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1), camera);
    const hit = ray.intersectObjects(scene.children, true).find((h) => h.object.userData.part && h.object.parent.scale.x !== 0 &&
                                                                    parts[h.object.userData.part].scale.x > 0);
    select(hit ? hit.object.userData.part : null);
  });
  document.querySelectorAll('table#parts tr, table#summary tr').forEach((tr) => {
    tr.addEventListener('click', () => {
      const cell = Array.from(tr.querySelectorAll('td')).find((td) => td.textContent in parts);
      if (cell) select(cell.textContent);
    });
  });
});
)JS";

}  // namespace

std::string orderView(const Assembly& a, const eval::SequencePlan& plan) {
  const std::filesystem::path dir(VAW_THREE_JS_DIR);
  const std::string three = readAll(dir / "three.min.js");
  const std::string loader = readAll(dir / "examples/js/loaders/GLTFLoader.js");
  const std::string controls = readAll(dir / "examples/js/controls/OrbitControls.js");
  if (three.empty() || loader.empty() || controls.empty())
    return "<h2>In 3D</h2>\n<p>No 3D view: three.js was not found in " + dir.string() +
           " (Debian's libjs-three). The pictures below show the order.</p>\n";
  const double stepSeconds = 1.0;
  const std::vector<std::uint8_t> bytes = glb(a, orderMotion(a, plan, stepSeconds, 20.0));
  nlohmann::json data;
  data["stepSeconds"] = stepSeconds;
  data["steps"] = nlohmann::json::array();
  for (const PartId p : plan.order) {
    data["steps"].push_back(a.parts[p].name);
    const Eigen::Vector3d away = orderApproach(a, plan, p);
    data["away"][a.parts[p].name] = {away.x(), away.y(), away.z()};
  }
  std::string h =
      "<h2>In 3D</h2>\n<p>The order played: each part flies home along its way in its step. Drag to turn, wheel to zoom, "
      "right-drag to pan; click a part to find its row, or a row to find its part.</p>\n"
      "<div id='view3d' style='width:100%;height:520px;border:1px solid #ccc'>"
      "<canvas id='view3d-canvas' style='width:100%;height:100%;display:block'></canvas></div>\n"
      "<p id='view3d-controls'><button id='view3d-play'>Play</button> step <input type='range' id='view3d-step' min='0' max='" +
      std::to_string(plan.order.empty() ? 0 : plan.order.size() - 1) + "' value='" +
      std::to_string(plan.order.empty() ? 0 : plan.order.size() - 1) +
      "' style='width:50%'> <span id='view3d-label'></span> <label><input type='checkbox' id='view3d-exploded'> "
      "exploded</label></p>\n";
  h += "<script type='application/json' id='view3d-data'>" + scriptText(data.dump()) + "</script>\n";
  h += "<script type='application/octet-stream' id='view3d-glb'>" + detail::base64(std::string(bytes.begin(), bytes.end())) + "</script>\n";
  h += "<script>" + scriptText(three) + "</script>\n<script>" + scriptText(loader) + "</script>\n<script>" +
       scriptText(controls) + "</script>\n<script>" + scriptText(kViewScript) + "</script>\n";
  return h;
}

}  // namespace vaw::report
