// tabula's report page: 3D replays of recorded runs (three.js, vendored) and a
// self-check the browser test reads. No network: everything comes from files beside
// index.html, loaded as classic scripts (browsers refuse modules and fetch() from disk).
(function () {
  "use strict";
  var errors = [];
  window.addEventListener("error", function (e) {
    var what = e.message || (e.target && (e.target.src || e.target.href)) || "error";
    errors.push(String(what));
  }, true);
  var consoleError = console.error;
  console.error = function () {
    errors.push(Array.prototype.map.call(arguments, String).join(" "));
    consoleError.apply(console, arguments);
  };

  function lerp(a, b, f) { return a + (b - a) * f; }

  // Orbit, zoom and pan around a target, z up (robotics' convention), as RViz's
  // orbit view does: left drag turns, right or shift drag pans, the wheel zooms.
  function Orbit(camera, dom, target, distance) {
    this.camera = camera;
    this.target = target.clone();
    this.distance = distance;
    this.azimuth = -2.2;
    this.elevation = 0.55;
    var self = this, last = null, panning = false;
    dom.addEventListener("contextmenu", function (e) { e.preventDefault(); });
    dom.addEventListener("pointerdown", function (e) {
      last = [e.clientX, e.clientY];
      panning = e.button === 2 || e.shiftKey;
      dom.setPointerCapture(e.pointerId);
    });
    dom.addEventListener("pointerup", function () { last = null; });
    dom.addEventListener("pointermove", function (e) {
      if (!last) return;
      var dx = e.clientX - last[0], dy = e.clientY - last[1];
      last = [e.clientX, e.clientY];
      if (panning) {
        var right = new THREE.Vector3().setFromMatrixColumn(self.camera.matrix, 0);
        var up = new THREE.Vector3().setFromMatrixColumn(self.camera.matrix, 1);
        var s = self.distance * 0.0015;
        self.target.addScaledVector(right, -dx * s).addScaledVector(up, dy * s);
      } else {
        self.azimuth -= dx * 0.008;
        self.elevation = Math.max(-1.5, Math.min(1.5, self.elevation + dy * 0.008));
      }
      self.update();
    });
    dom.addEventListener("wheel", function (e) {
      e.preventDefault();
      self.distance *= Math.exp(e.deltaY * 0.001);
      self.update();
    }, { passive: false });
    this.update();
  }
  Orbit.prototype.update = function () {
    var c = Math.cos(this.elevation);
    this.camera.position.set(
      this.target.x + this.distance * c * Math.cos(this.azimuth),
      this.target.y + this.distance * c * Math.sin(this.azimuth),
      this.target.z + this.distance * Math.sin(this.elevation));
    this.camera.lookAt(this.target);
    if (this.onchange) this.onchange();
  };

  function bodyMesh(b) {
    var g = new THREE.BufferGeometry();
    g.setAttribute("position", new THREE.Float32BufferAttribute(b.vertices, 3));
    g.setIndex(b.triangles);
    g = g.toNonIndexed();
    g.computeVertexNormals();
    var color = new THREE.Color(b.color[0], b.color[1], b.color[2]);
    var m = new THREE.Mesh(g, new THREE.MeshLambertMaterial({ color: color }));
    if (b.kind === "floor") m.material.color.multiplyScalar(0.9);
    return m;
  }

  function setPose(m, p, o) {
    m.position.set(p[o], p[o + 1], p[o + 2]);
    m.quaternion.set(p[o + 3], p[o + 4], p[o + 5], p[o + 6]);
  }

  // One replay in `box`: a canvas, a time slider, play/pause and speed.
  function Replay(box, data) {
    var canvas = box.querySelector("canvas");
    var slider = box.querySelector("input[type=range]");
    var play = box.querySelector("button");
    var speed = box.querySelector("select");
    var clock = box.querySelector(".clock");
    var renderer = new THREE.WebGLRenderer({ canvas: canvas, antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setSize(canvas.clientWidth, canvas.clientHeight, false);
    renderer.setClearColor(0xdde6f0);
    var scene = new THREE.Scene();
    scene.add(new THREE.HemisphereLight(0xffffff, 0x667788, 0.75));
    var sun = new THREE.DirectionalLight(0xffffff, 0.6);
    sun.position.set(2, 1.5, 4);
    scene.add(sun);
    var camera = new THREE.PerspectiveCamera(45, canvas.clientWidth / canvas.clientHeight, 0.02, 200);
    camera.up.set(0, 0, 1);

    var meshes = data.bodies.map(function (b) {
      var m = bodyMesh(b);
      setPose(m, b.pose, 0);
      scene.add(m);
      return m;
    });
    var box3 = new THREE.Box3();
    data.bodies.forEach(function (b, i) {
      if (b.kind !== "floor") box3.expandByObject(meshes[i]);
    });
    if (box3.isEmpty()) box3.setFromCenterAndSize(new THREE.Vector3(), new THREE.Vector3(1, 1, 1));
    var centre = box3.getCenter(new THREE.Vector3());
    var size = box3.getSize(new THREE.Vector3()).length();
    var orbit = new Orbit(camera, canvas, centre, Math.max(1.0, 1.3 * size));
    var grid = new THREE.GridHelper(Math.ceil(size * 2 + 2), Math.ceil(size * 2 + 2) * 2, 0x99a4b0, 0xbfc8d2);
    grid.rotation.x = Math.PI / 2;
    grid.position.z = 0.001;
    scene.add(grid);

    var times = data.times, n = times.length;
    var duration = n ? times[n - 1] : 0;
    var t = 0, playing = false, lastWall = null;
    slider.max = String(Math.max(1, Math.round(duration * 100)));

    function show(time) {
      t = Math.max(0, Math.min(duration, time));
      // The last frame at or before t, blended towards the next one.
      var lo = 0, hi = n - 1;
      while (lo < hi) {
        var mid = (lo + hi + 1) >> 1;
        if (times[mid] <= t) lo = mid; else hi = mid - 1;
      }
      var a = data.frames[lo], nb = Math.min(lo + 1, n - 1), b = data.frames[nb];
      var f = nb > lo && times[nb] > times[lo] ? (t - times[lo]) / (times[nb] - times[lo]) : 0;
      var q1 = new THREE.Quaternion(), q2 = new THREE.Quaternion();
      data.moving.forEach(function (bi, k) {
        var o = 7 * k, m = meshes[bi];
        m.position.set(lerp(a[o], b[o], f), lerp(a[o + 1], b[o + 1], f), lerp(a[o + 2], b[o + 2], f));
        q1.set(a[o + 3], a[o + 4], a[o + 5], a[o + 6]);
        q2.set(b[o + 3], b[o + 4], b[o + 5], b[o + 6]);
        m.quaternion.copy(q1.slerp(q2, f));
      });
      var mark = "";
      data.marks.forEach(function (mk) { if (mk[0] <= t + 1e-6) mark = mk[1]; });
      clock.textContent = t.toFixed(2) + " / " + duration.toFixed(2) + " s" + (mark ? " — " + mark : "");
      slider.value = String(Math.round(t * 100));
      renderer.render(scene, camera);
    }
    orbit.onchange = function () { renderer.render(scene, camera); };
    slider.addEventListener("input", function () { playing = false; play.textContent = "play"; show(slider.value / 100); });
    play.addEventListener("click", function () {
      if (!playing && t >= duration) t = 0;
      playing = !playing;
      play.textContent = playing ? "pause" : "play";
      lastWall = null;
      if (playing) requestAnimationFrame(tick);
    });
    function tick(now) {
      if (!playing) return;
      if (lastWall !== null) show(t + (now - lastWall) / 1000 * Number(speed.value));
      lastWall = now;
      if (t >= duration) { playing = false; play.textContent = "play"; return; }
      requestAnimationFrame(tick);
    }
    show(0);

    // How many distinct colours the canvas shows: a blank or failed view has one.
    this.colours = function () {
      var gl = renderer.getContext();
      var w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
      var px = new Uint8Array(w * h * 4);
      gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
      var seen = {}, count = 0;
      for (var i = 0; i < px.length; i += 4 * 7) {
        var key = px[i] + "," + px[i + 1] + "," + px[i + 2];
        if (!seen[key]) { seen[key] = true; count++; }
      }
      return count;
    };
  }

  function selfCheck(replays) {
    var images = Array.prototype.slice.call(document.images);
    var pending = images.filter(function (im) { return !im.complete; });
    function report() {
      var broken = images.filter(function (im) { return !im.complete || im.naturalWidth === 0; })
        .map(function (im) { return im.getAttribute("src"); });
      var views = replays.map(function (r) { return { id: r.id, colours: r.view ? r.view.colours() : 0, error: r.error || null }; });
      var ok = errors.length === 0 && broken.length === 0 && views.every(function (v) { return v.colours > 8; });
      var out = document.getElementById("selftest");
      out.textContent = JSON.stringify({ ok: ok, images: images.length, broken: broken, replays: views, errors: errors });
      document.body.setAttribute("data-selftest", ok ? "ok" : "failed");
    }
    if (!pending.length) return report();
    var left = pending.length;
    pending.forEach(function (im) {
      var done = function () { if (--left === 0) report(); };
      im.addEventListener("load", done);
      im.addEventListener("error", done);
    });
  }

  window.addEventListener("load", function () {
    var data = window.TABULA_REPLAYS || {};
    var replays = Array.prototype.map.call(document.querySelectorAll(".replay"), function (box) {
      var id = box.getAttribute("data-replay"), r = { id: id };
      try {
        if (typeof THREE === "undefined") throw new Error("three.js did not load");
        if (!data[id]) throw new Error("replay data " + id + " did not load");
        r.view = new Replay(box, data[id]);
      } catch (e) {
        r.error = String(e);
        errors.push(r.error);
      }
      return r;
    });
    selfCheck(replays);
  });
})();
