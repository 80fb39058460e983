// The 3D replay of a case page (docs/report.md#3d-replay): draws window.PBDVAL_REPLAY (written
// by python/pbdval/replay.py) with three.js (the global THREE of assets/three.min.js and
// THREE.OrbitControls). One colour per engine/method, static bodies grey; deformables from the
// particles each run read back: cloth and solid surfaces (data.particles.surfaces), rods as
// polylines (.lines), fluids as points (.points). Between frames the positions (bodies and
// particles) are interpolated linearly and the rotations by slerp.
// window.pbdvalReplay exposes the state to the report's browser test.
(function () {
  "use strict";
  var data = window.PBDVAL_REPLAY;
  var root = document.getElementById("replay");
  if (!root) return;
  function note(text) {
    var p = document.createElement("p");
    p.className = "badge warn";
    p.textContent = text;
    root.appendChild(p);
  }
  if (!data) { note("no replay data for this case"); return; }
  if (typeof THREE === "undefined") { note("three.js is missing from assets/ (run scripts/install-deps, then rebuild the report)"); return; }

  function floats(text) {
    var bytes = atob(text), buffer = new ArrayBuffer(bytes.length), view = new Uint8Array(buffer);
    for (var i = 0; i < bytes.length; ++i) view[i] = bytes.charCodeAt(i);
    return new Float32Array(buffer);
  }
  function integers(text) {
    var bytes = atob(text), buffer = new ArrayBuffer(bytes.length), view = new Uint8Array(buffer);
    for (var i = 0; i < bytes.length; ++i) view[i] = bytes.charCodeAt(i);
    return new Uint32Array(buffer);
  }

  // --- controls -------------------------------------------------------------------------------
  var bar = document.createElement("div");
  bar.className = "replay-controls";
  var play = document.createElement("button");
  play.id = "replay-play";
  play.textContent = "play";
  var speed = document.createElement("select");
  speed.id = "replay-speed";
  [0.1, 0.25, 0.5, 1, 2, 4].forEach(function (s) {
    var option = document.createElement("option");
    option.value = String(s);
    option.textContent = s + "×";
    if (s === 1) option.selected = true;
    speed.appendChild(option);
  });
  var scrubber = document.createElement("input");
  scrubber.type = "range";
  scrubber.id = "replay-time";
  scrubber.min = "0";
  scrubber.max = String(data.duration);
  scrubber.step = "any";
  scrubber.value = "0";
  scrubber.style.width = "420px";
  var label = document.createElement("span");
  label.id = "replay-label";
  bar.appendChild(play);
  bar.appendChild(document.createTextNode(" speed "));
  bar.appendChild(speed);
  bar.appendChild(document.createTextNode(" "));
  bar.appendChild(scrubber);
  bar.appendChild(document.createTextNode(" "));
  bar.appendChild(label);
  root.appendChild(bar);
  var legend = document.createElement("div");
  legend.className = "replay-legend";
  root.appendChild(legend);

  var canvasHolder = document.createElement("div");
  root.appendChild(canvasHolder);
  var width = 900, height = 480;
  var renderer;
  try {
    renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  } catch (error) {
    note("WebGL is not available in this browser: the replay cannot be drawn (" + error.message + ")");
    window.pbdvalReplay = { ready: false };
    return;
  }
  renderer.setSize(width, height);
  renderer.setClearColor(0xffffff);
  canvasHolder.appendChild(renderer.domElement);

  var scene = new THREE.Scene();
  scene.add(new THREE.HemisphereLight(0xffffff, 0x888888, 0.9));
  var sun = new THREE.DirectionalLight(0xffffff, 0.6);
  sun.position.set(3, 10, 6);
  scene.add(sun);

  // --- geometry -------------------------------------------------------------------------------
  var geometries = {};
  function geometryOf(draw) {
    var key = JSON.stringify(draw);
    if (geometries[key]) return geometries[key];
    var g;
    if (draw.mesh !== undefined) {
      var mesh = data.meshes[draw.mesh];
      g = new THREE.BufferGeometry();
      g.setAttribute("position", new THREE.BufferAttribute(floats(mesh.v), 3));
      g.setIndex(new THREE.BufferAttribute(integers(mesh.f), 1));
      g.computeVertexNormals();
    } else if (draw.box !== undefined) {
      g = new THREE.BoxGeometry(draw.box[0], draw.box[1], draw.box[2]);
    } else if (draw.cylinder !== undefined) {
      g = new THREE.CylinderGeometry(draw.cylinder[0], draw.cylinder[0], draw.cylinder[1], 32);
    } else {
      g = new THREE.SphereGeometry(draw.sphere, 24, 16);
    }
    geometries[key] = g;
    return g;
  }
  // A body: an outer object at the centre of mass with the body's rotation, holding the
  // geometry shifted by −c (the centre of mass in the scene frame).
  function makeBody(body, material) {
    var outer = new THREE.Object3D();
    var inner = new THREE.Mesh(geometryOf(body.draw), material);
    inner.position.set(-body.com[0], -body.com[1], -body.com[2]);
    outer.add(inner);
    scene.add(outer);
    return outer;
  }
  var bounds = new THREE.Box3();
  var grey = new THREE.MeshStandardMaterial({ color: 0xb0b0b0, roughness: 0.9 });
  data.bodies.forEach(function (body) {
    if (body.dynamic) return;
    var object = makeBody(body, grey);
    var q = body.rotation, p = body.position;
    object.quaternion.set(q[1], q[2], q[3], q[0]);
    // The resolved pose gives the scene frame's origin; the object sits at the centre of mass.
    var com = new THREE.Vector3(body.com[0], body.com[1], body.com[2]).applyQuaternion(object.quaternion);
    object.position.set(p[0] + com.x, p[1] + com.y, p[2] + com.z);
  });

  var times = floats(data.times);
  var bodyCount = data.dynamicIds.length;
  var particleCount = data.particles ? data.particles.particleCount : 0;
  var dynamicBodies = data.bodies.filter(function (b) { return b.dynamic; });
  var runs = data.runs.map(function (run) {
    var material = new THREE.MeshStandardMaterial({ color: new THREE.Color(run.colour), roughness: 0.6,
                                                     transparent: true, opacity: 0.85 });
    var objects = dynamicBodies.map(function (body) { return makeBody(body, material); });
    var entry = { label: run.label, frames: run.frames, x: floats(run.x), q: floats(run.q), objects: objects,
                  visible: true, p: run.p ? floats(run.p) : null, particleObjects: [], particlePositions: null };
    for (var f = 0; f < entry.frames; ++f)
      for (var b = 0; b < bodyCount; ++b) {
        var i = 3 * (f * bodyCount + b);
        bounds.expandByPoint(new THREE.Vector3(entry.x[i], entry.x[i + 1], entry.x[i + 2]));
      }
    if (entry.p) {
      // One position buffer per run, shared by its surfaces, polylines and points.
      entry.particlePositions = new THREE.BufferAttribute(new Float32Array(3 * particleCount), 3);
      entry.particlePositions.setUsage(THREE.DynamicDrawUsage);
      for (var k = 0; k < entry.frames * particleCount; ++k)
        bounds.expandByPoint(new THREE.Vector3(entry.p[3 * k], entry.p[3 * k + 1], entry.p[3 * k + 2]));
      var colour = new THREE.Color(run.colour);
      data.particles.surfaces.forEach(function (faces) {
        var g = new THREE.BufferGeometry();
        g.setAttribute("position", entry.particlePositions);
        g.setIndex(new THREE.BufferAttribute(integers(faces), 1));
        var surface = new THREE.Mesh(g, new THREE.MeshStandardMaterial({ color: colour, roughness: 0.7,
          side: THREE.DoubleSide, transparent: true, opacity: 0.8 }));
        var edges = new THREE.Mesh(g, new THREE.MeshBasicMaterial({ color: colour, wireframe: true }));
        entry.particleObjects.push(surface, edges);
      });
      data.particles.lines.forEach(function (indices) {
        var g = new THREE.BufferGeometry();
        g.setAttribute("position", entry.particlePositions);
        g.setIndex(new THREE.BufferAttribute(integers(indices), 1));
        // An index list drawn as a strip: consecutive particles joined.
        entry.particleObjects.push(new THREE.Line(g, new THREE.LineBasicMaterial({ color: colour })));
        entry.particleObjects.push(new THREE.Points(g, new THREE.PointsMaterial({ color: colour, size: 4,
          sizeAttenuation: false })));
      });
      if (data.particles.points) {
        var g = new THREE.BufferGeometry();
        g.setAttribute("position", entry.particlePositions);
        g.setIndex(new THREE.BufferAttribute(integers(data.particles.points), 1));
        entry.particleObjects.push(new THREE.Points(g, new THREE.PointsMaterial({ color: colour, size: 3,
          sizeAttenuation: false })));
      }
      entry.particleObjects.forEach(function (object) { object.frustumCulled = false; scene.add(object); });
    }
    var item = document.createElement("label");
    var box = document.createElement("input");
    box.type = "checkbox";
    box.checked = true;
    box.addEventListener("change", function () { entry.visible = box.checked; draw(); });
    var swatch = document.createElement("span");
    swatch.className = "swatch";
    swatch.style.background = run.colour;
    item.appendChild(box);
    item.appendChild(swatch);
    item.appendChild(document.createTextNode(run.label + (run.frames < data.frameCount ? " (stops: diverged)" : "")));
    legend.appendChild(item);
    return entry;
  });
  if (bounds.isEmpty()) bounds.setFromCenterAndSize(new THREE.Vector3(), new THREE.Vector3(2, 2, 2));
  // The bodies reach beyond their centres of mass: grow the box by the largest body's radius.
  var reach = 0;
  dynamicBodies.forEach(function (body) {
    var g = geometryOf(body.draw);
    g.computeBoundingSphere();
    reach = Math.max(reach, g.boundingSphere.radius + Math.hypot(body.com[0], body.com[1], body.com[2]));
  });
  bounds.expandByScalar(reach);

  var centre = bounds.getCenter(new THREE.Vector3());
  var size = Math.max(0.2, bounds.getSize(new THREE.Vector3()).length());
  var camera = new THREE.PerspectiveCamera(40, width / height, size / 100, size * 50);
  camera.position.set(centre.x + 0.55 * size, centre.y + 0.35 * size, centre.z + 0.85 * size);
  camera.lookAt(centre);
  var controls = THREE.OrbitControls ? new THREE.OrbitControls(camera, renderer.domElement) : null;
  if (controls) {
    controls.target.copy(centre);
    controls.addEventListener("change", function () { renderer.render(scene, camera); });
    controls.update();
  }

  // --- time -----------------------------------------------------------------------------------
  var time = 0, playing = false, last = null;
  var qa = new THREE.Quaternion(), qb = new THREE.Quaternion();
  function frameAt(t) {  // the last frame at or before t
    var low = 0, high = times.length - 1;
    while (low < high) {
      var mid = (low + high + 1) >> 1;
      if (times[mid] <= t) low = mid; else high = mid - 1;
    }
    return low;
  }
  function draw() {
    var f = frameAt(time);
    var g = Math.min(f + 1, times.length - 1);
    var s = g > f ? (time - times[f]) / (times[g] - times[f]) : 0;
    runs.forEach(function (run) {
      var shown = run.visible && f < run.frames;
      var h = Math.min(g, run.frames - 1);
      run.particleObjects.forEach(function (object) { object.visible = shown; });
      if (shown && run.p) {
        var target = run.particlePositions.array;
        var a0 = 3 * f * particleCount, a1 = 3 * h * particleCount;
        for (var k = 0; k < 3 * particleCount; ++k)
          target[k] = run.p[a0 + k] + s * (run.p[a1 + k] - run.p[a0 + k]);
        run.particlePositions.needsUpdate = true;
        run.particleObjects.forEach(function (object) {
          if (object.isMesh && !object.material.wireframe) object.geometry.computeVertexNormals();
        });
      }
      run.objects.forEach(function (object, b) {
        object.visible = shown;
        if (!shown) return;
        var i = 3 * (f * bodyCount + b), j = 3 * (h * bodyCount + b);
        object.position.set(run.x[i] + s * (run.x[j] - run.x[i]), run.x[i + 1] + s * (run.x[j + 1] - run.x[i + 1]),
                            run.x[i + 2] + s * (run.x[j + 2] - run.x[i + 2]));
        var k = 4 * (f * bodyCount + b), m = 4 * (h * bodyCount + b);
        qa.set(run.q[k + 1], run.q[k + 2], run.q[k + 3], run.q[k]);
        qb.set(run.q[m + 1], run.q[m + 2], run.q[m + 3], run.q[m]);
        object.quaternion.copy(qa).slerp(qb, s);
      });
    });
    label.textContent = "t = " + time.toFixed(3) + " s of " + data.duration.toFixed(3) + " s";
    scrubber.value = String(time);
    renderer.render(scene, camera);
  }
  function tick(now) {
    if (!playing) { last = null; return; }
    if (last !== null) {
      time += (now - last) / 1000 * parseFloat(speed.value);
      if (time >= data.duration) { time = data.duration; playing = false; play.textContent = "play"; }
    }
    last = now;
    draw();
    if (playing) requestAnimationFrame(tick);
  }
  play.addEventListener("click", function () {
    if (!playing && time >= data.duration) time = 0;
    playing = !playing;
    play.textContent = playing ? "pause" : "play";
    if (playing) requestAnimationFrame(tick);
  });
  scrubber.addEventListener("input", function () { time = parseFloat(scrubber.value); draw(); });
  draw();
  window.pbdvalReplay = {
    ready: true,
    time: function () { return time; },
    playing: function () { return playing; },
    runs: runs.length
  };
})();
