// pkmkit's offline views of a plan, a joint program (post, verify) or a workspace: the machine
// drawn to scale and posed by a slider, the tool path coloured by speed or deviation, the joints'
// charts with their limit bands, the report's numbers. Plain canvas, no library: the data comes
// already decimated from pkm (min/max buckets, a thinned path, a few hundred drawn moments).
(function () {
  'use strict';
  var data = JSON.parse(document.getElementById('pkm-data').textContent);
  var PART_STYLE = [
    {colour: '#59606e', width: 3},    // frame: base, rails, pulleys
    {colour: '#d9822b', width: 2.5},  // link: legs, struts, cables
    {colour: '#2a6fdb', width: 3},    // platform, effector
    {colour: '#1d2330', width: 2},    // tool
    {colour: '#a0a7b4', width: 1, dash: [5, 4]}  // work envelope
  ];
  // Colour ramp from slow or small (blue) to fast or large (red), as a viewer reads heat.
  var RAMP = [[49, 54, 149], [69, 117, 180], [116, 173, 209], [171, 217, 233], [254, 224, 144],
              [253, 174, 97], [244, 109, 67], [215, 48, 39], [165, 0, 38]];
  var BINS = 24;

  function rampColour(f) {
    f = Math.max(0, Math.min(1, f)) * (RAMP.length - 1);
    var i = Math.min(RAMP.length - 2, Math.floor(f)), r = f - i, a = RAMP[i], b = RAMP[i + 1];
    return 'rgb(' + [0, 1, 2].map(function (k) {
      return Math.round(a[k] + (b[k] - a[k]) * r);
    }).join(',') + ')';
  }
  function fmt(v) {
    if (typeof v !== 'number') return v === null || v === undefined ? '-' : String(v);
    if (Number.isInteger(v)) return String(v);
    return String(+v.toPrecision(9));
  }
  function short(v) {
    if (v !== 0 && Math.abs(v) < 1e-3) return v.toExponential(2);
    return String(+v.toPrecision(4));
  }
  function el(tag, text, cls) {
    var e = document.createElement(tag);
    if (text !== undefined) e.textContent = text;
    if (cls) e.className = cls;
    return e;
  }

  // ---- summary, marks, warnings ----
  function fillSummary() {
    var kinds = {plan: 'plan', post: 'joint program (pkm post)', verify: 'verification',
                 view: 'joint program (pkm view)', workspace: 'workspace'};
    document.getElementById('subtitle').textContent =
        (kinds[data.kind] || data.kind) + ' on ' + data.machine;
    var body = document.querySelector('#summary tbody');
    (data.summary || []).forEach(function (r) {
      var tr = el('tr');
      tr.dataset.key = r.key;
      if (r.bad) tr.className = 'bad';
      tr.appendChild(el('th', r.label));
      var td = el('td', fmt(r.value), 'value');
      td.dataset.value = JSON.stringify(r.value);
      tr.appendChild(td);
      tr.appendChild(el('td', r.unit));
      body.appendChild(tr);
    });
    var verdict = document.getElementById('verdict');
    if (data.verdict) {
      verdict.textContent = data.verdict;
      verdict.className = data.passed ? 'passed' : 'failed';
    }
    var marks = data.marks || [];
    document.getElementById('marks-title').textContent = marks.length ?
        (data.marks_title || 'Marked on the path') + ' (' + marks.length + ')' : '';
    document.getElementById('marks-note').textContent = marks.length ? data.marks_note || '' : '';
    var list = document.getElementById('marks');
    marks.slice(0, 500).forEach(function (m) {
      var li = el('li', m.label);
      li.addEventListener('click', function () { setT(m.t); });
      list.appendChild(li);
    });
    var warnings = (data.report && data.report.warnings) || [];
    document.getElementById('warnings-title').textContent =
        warnings.length ? 'Warnings (' + warnings.length + ')' : '';
    var wl = document.getElementById('warnings');
    warnings.slice(0, 200).forEach(function (w) {
      wl.appendChild(el('li', 'line ' + w.line + ': ' + w.message));
    });
  }

  // ---- the scene: machine, path, marks ----
  var scene = document.getElementById('scene');
  var view = {yaw: -0.6, pitch: 0.45, zoom: 1, panX: 0, panY: 0};
  var drawing = data.drawing || {fixed: [], t: [], frames: []};
  var path = data.path || {t: [], x: [], y: [], z: [], c: []};
  var planar = !!data.planar;
  var tRange = [0, 1];
  var currentT = 0;
  var fitPath = false;  // frame the whole machine, or only the tool path
  var bounds = sceneBounds();
  var pathLayer = document.createElement('canvas');
  var pathLayerKey = '';

  function sceneBounds() {
    var lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    function add(x, y, z) {
      var p = [x, y, z];
      for (var k = 0; k < 3; ++k) {
        if (p[k] === null || !isFinite(p[k])) continue;
        lo[k] = Math.min(lo[k], p[k]);
        hi[k] = Math.max(hi[k], p[k]);
      }
    }
    function addFlat(flat) {
      for (var i = 0; i + 6 < flat.length; i += 7) {
        add(flat[i + 1], flat[i + 2], flat[i + 3]);
        add(flat[i + 4], flat[i + 5], flat[i + 6]);
      }
    }
    if (!fitPath || !path.x.length) {
      addFlat(drawing.fixed);
      drawing.frames.forEach(function (f, i) { if (i % 10 === 0) addFlat(f.parts); });
    }
    for (var i = 0; i < path.x.length; ++i) add(path.x[i], path.y[i], path.z[i]);
    var job = data.job_outline;
    if (job) for (var o = 0; o < job.x.length; ++o) add(job.x[o], job.y[o], job.z[o]);
    ['inside', 'boundary'].forEach(function (kind) {
      var cells = (data.cells && data.cells[kind]) || [];
      for (var j = 0; j + 3 < cells.length; j += 4) add(cells[j], cells[j + 1], cells[j + 2]);
    });
    for (var k = 0; k < 3; ++k) if (!isFinite(lo[k])) { lo[k] = -1; hi[k] = 1; }
    var centre = [0, 1, 2].map(function (k) { return (lo[k] + hi[k]) / 2; });
    var radius = Math.max(1e-9, Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) / 2);
    return {lo: lo, hi: hi, centre: centre, radius: radius};
  }

  // Screen position of a machine point: planar machines from the front (x right, y up); the
  // others turned about z by yaw and tilted by pitch, orthographic, z up.
  function projector() {
    var w = scene.width, h = scene.height, c = bounds.centre;
    var scale, cy = Math.cos(view.yaw), sy = Math.sin(view.yaw);
    var cp = Math.cos(view.pitch), sp = Math.sin(view.pitch);
    if (planar) {
      var sx = (bounds.hi[0] - bounds.lo[0]) || 1, syy = (bounds.hi[1] - bounds.lo[1]) || 1;
      scale = 0.9 * Math.min(w / sx, h / syy) * view.zoom;
    } else {
      scale = 0.9 * Math.min(w, h) / (2 * bounds.radius) * view.zoom;
    }
    var ox = w / 2 + view.panX, oy = h / 2 + view.panY;
    if (planar) {
      return function (x, y) { return [ox + (x - c[0]) * scale, oy - (y - c[1]) * scale]; };
    }
    return function (x, y, z) {
      var dx = x - c[0], dy = y - c[1], dz = z - c[2];
      var rx = cy * dx - sy * dy, ry = sy * dx + cy * dy;
      return [ox + rx * scale, oy - (dz * cp + ry * sp) * scale];
    };
  }

  function colourMax() {
    var m = 0;
    for (var i = 0; i < path.c.length; ++i) if (path.c[i] > m) m = path.c[i];
    return m > 0 ? m : 1;
  }
  var cMax = colourMax();

  // The path, one stroke per colour bin, drawn once per view (not per slider move).
  function drawPathLayer(project) {
    var key = [scene.width, scene.height, view.yaw, view.pitch, view.zoom, view.panX, view.panY,
               fitPath].join();
    if (key === pathLayerKey) return;
    pathLayerKey = key;
    pathLayer.width = scene.width;
    pathLayer.height = scene.height;
    var g = pathLayer.getContext('2d');
    g.lineWidth = 1.6;
    g.lineCap = 'round';
    var n = path.x.length, screen = new Float64Array(2 * n);
    for (var i = 0; i < n; ++i) {
      var p = project(path.x[i], path.y[i], path.z[i]);
      screen[2 * i] = p[0];
      screen[2 * i + 1] = p[1];
    }
    var job = data.job_outline;
    if (job && job.x.length > 1) {  // where the blocks should have gone, under them
      g.beginPath();
      for (var o = 0; o < job.x.length; ++o) {
        var q = project(job.x[o], job.y[o], job.z[o]);
        if (o === 0) g.moveTo(q[0], q[1]); else g.lineTo(q[0], q[1]);
      }
      g.strokeStyle = '#c9ced8';
      g.lineWidth = 4;
      g.stroke();
      g.lineWidth = 1.6;
    }
    var pen = path.p;  // plotters: 0 where the pen was up on the way to a point
    if (pen) {  // pen-up travel grey and dashed, under the drawing
      g.beginPath();
      for (var u = 1; u < n; ++u) {
        if (pen[u]) continue;
        g.moveTo(screen[2 * u - 2], screen[2 * u - 1]);
        g.lineTo(screen[2 * u], screen[2 * u + 1]);
      }
      g.strokeStyle = '#9aa1ad';
      g.lineWidth = 1;
      g.setLineDash([4, 4]);
      g.stroke();
      g.setLineDash([]);
      g.lineWidth = 1.6;
    }
    for (var b = 0; b < BINS; ++b) {
      g.beginPath();
      for (var j = 1; j < n; ++j) {
        if (pen && !pen[j]) continue;
        var bin = Math.min(BINS - 1, Math.floor(path.c[j] / cMax * BINS));
        if (bin !== b) continue;
        g.moveTo(screen[2 * j - 2], screen[2 * j - 1]);
        g.lineTo(screen[2 * j], screen[2 * j + 1]);
      }
      g.strokeStyle = rampColour((b + 0.5) / BINS);
      g.stroke();
    }
    drawCells(g, project);
    drawBlockEnds(g, screen, n);
  }

  // Block ends as small light dots, each at least BLOCK_END_GAP pixels from the last one drawn,
  // so that where blocks crowd (a circle) the deviation's colour still shows.
  var BLOCK_END_GAP = 8;
  function drawBlockEnds(g, screen, n) {
    if (!data.block_ends) return;
    g.fillStyle = 'rgba(29, 35, 48, 0.45)';
    var lastX = -Infinity, lastY = -Infinity, drawn = 0;
    for (var k = 0; k < n; ++k) {
      var x = screen[2 * k], y = screen[2 * k + 1];
      if (Math.hypot(x - lastX, y - lastY) < BLOCK_END_GAP) continue;
      g.fillRect(x - 1, y - 1, 2, 2);
      lastX = x;
      lastY = y;
      ++drawn;
    }
    window.pkmView.blockEndsDrawn = drawn;
  }

  // Workspace cells: inside green, boundary orange; squares to scale on a planar machine, smaller
  // squares at their centres otherwise.
  function drawCells(g, project) {
    if (!data.cells) return;
    [['boundary', 'rgba(230, 126, 34, 0.55)'], ['inside', 'rgba(39, 174, 96, 0.45)']]
        .forEach(function (kind) {
          var flat = data.cells[kind[0]] || [];
          g.fillStyle = kind[1];
          for (var i = 0; i + 3 < flat.length; i += 4) {
            var p = project(flat[i], flat[i + 1], flat[i + 2]);
            if (planar) {
              var q = project(flat[i] + flat[i + 3], flat[i + 1] + flat[i + 3], flat[i + 2]);
              var size = Math.max(1, q[0] - p[0]);
              g.fillRect(p[0] - size / 2, p[1] - size / 2, size, size);
            } else {  // a square of 60 % of the cell's projected edge at its centre
              var e = project(flat[i] + flat[i + 3], flat[i + 1], flat[i + 2]);
              var side = Math.max(2, 0.6 * Math.hypot(e[0] - p[0], e[1] - p[1]));
              g.fillRect(p[0] - side / 2, p[1] - side / 2, side, side);
            }
          }
        });
  }

  function drawSegments(g, project, flat) {
    for (var part = 0; part < PART_STYLE.length; ++part) {
      var style = PART_STYLE[part];
      g.beginPath();
      for (var i = 0; i + 6 < flat.length; i += 7) {
        if (flat[i] !== part) continue;
        var a = project(flat[i + 1], flat[i + 2], flat[i + 3]);
        var b = project(flat[i + 4], flat[i + 5], flat[i + 6]);
        g.moveTo(a[0], a[1]);
        g.lineTo(b[0], b[1]);
      }
      g.strokeStyle = style.colour;
      g.lineWidth = style.width;
      g.setLineDash(style.dash || []);
      g.stroke();
      g.setLineDash([]);
      if (part === 1) {  // joints at both ends of legs, struts and cables
        g.fillStyle = '#59606e';
        for (var j = 0; j + 6 < flat.length; j += 7) {
          if (flat[j] !== 1) continue;
          [1, 4].forEach(function (o) {
            var p = project(flat[j + o], flat[j + o + 1], flat[j + o + 2]);
            g.beginPath();
            g.arc(p[0], p[1], 3, 0, 2 * Math.PI);
            g.fill();
          });
        }
      }
    }
  }

  // Index of the last entry of sorted `times` at or before t (0 when none).
  function indexAt(times, t) {
    var lo = 0, hi = times.length - 1;
    if (hi < 0) return -1;
    while (lo < hi) {
      var mid = (lo + hi + 1) >> 1;
      if (times[mid] <= t) lo = mid; else hi = mid - 1;
    }
    return lo;
  }

  function toolAt(t) {
    var i = indexAt(path.t, t);
    if (i < 0) return null;
    if (i + 1 >= path.t.length || path.t[i + 1] === path.t[i]) return [path.x[i], path.y[i], path.z[i]];
    var r = Math.max(0, Math.min(1, (t - path.t[i]) / (path.t[i + 1] - path.t[i])));
    return [0, 1, 2].map(function (k) {
      var a = [path.x, path.y, path.z][k];
      return a[i] + (a[i + 1] - a[i]) * r;
    });
  }

  function drawScene() {
    var g = scene.getContext('2d');
    var project = projector();
    g.fillStyle = '#ffffff';
    g.fillRect(0, 0, scene.width, scene.height);
    drawPathLayer(project);
    g.drawImage(pathLayer, 0, 0);
    drawSegments(g, project, drawing.fixed);
    var f = indexAt(drawing.t, currentT);
    if (f >= 0 && f + 1 < drawing.t.length &&
        drawing.t[f + 1] - currentT < currentT - drawing.t[f]) {
      f += 1;  // the nearest drawn moment
    }
    if (f >= 0) drawSegments(g, project, drawing.frames[f].parts);
    window.pkmView.drawnMoment = f;
    showTensions(f);
    // Marked moves as small red rings: many of them must not hide the path.
    g.strokeStyle = 'rgba(179, 38, 30, 0.8)';
    g.lineWidth = 1.2;
    (data.marks || []).forEach(function (m) {
      var p = project(m.x, m.y, m.z);
      g.beginPath();
      g.arc(p[0], p[1], 4, 0, 2 * Math.PI);
      g.stroke();
    });
    // The tool dot where the drawn machine holds it (its moment), so the two never part.
    var tool = f >= 0 && drawing.frames[f].tool ? drawing.frames[f].tool : toolAt(currentT);
    window.pkmView.toolDrawn = tool ? project(tool[0], tool[1], tool[2]) : null;
    if (tool) {
      var p = project(tool[0], tool[1], tool[2]);
      g.fillStyle = '#111';
      g.beginPath();
      g.arc(p[0], p[1], 4.5, 0, 2 * Math.PI);
      g.fill();
    }
    if (!planar) drawAxes(g);
  }

  // A machine hung on cables: each cable's tension at rest at the drawn moment, and the least
  // and greatest over the drawn moments (a sample of the path, said so).
  var tensionRange = tensionExtremes();
  function tensionExtremes() {
    var cables = drawing.cables;
    if (!cables) return null;
    var lo = {N: Infinity}, hi = {N: -Infinity};
    drawing.frames.forEach(function (frame) {
      if (!frame.tensions) return;
      frame.tensions.N.forEach(function (n, c) {
        if (n < lo.N) lo = {N: n, cable: cables.names[c]};
        if (n > hi.N) hi = {N: n, cable: cables.names[c]};
      });
    });
    return isFinite(lo.N) ? {lo: lo, hi: hi} : null;
  }
  function showTensions(f) {
    var readout = document.getElementById('tension-readout');
    var cables = drawing.cables;
    if (!cables || !readout) return;
    var frame = f >= 0 ? drawing.frames[f] : null;
    var text;
    if (frame && frame.tensions) {
      text = 'cable tensions at rest here: ' + frame.tensions.N.map(function (n, c) {
        return cables.names[c] + ' ' + n.toFixed(2) + ' N';
      }).join(', ') + ' (limits ' + cables.limits + ')';
      if (!frame.tensions.held) text += ': no tensions within the limits hold the effector here';
    } else {
      text = 'cable tensions at rest here: no balance (a cable would have no direction)';
    }
    if (tensionRange) {
      text += '; over the ' + drawing.frames.length + ' drawn moments of the path: least ' +
              tensionRange.lo.N.toFixed(2) + ' N (' + tensionRange.lo.cable + '), greatest ' +
              tensionRange.hi.N.toFixed(2) + ' N (' + tensionRange.hi.cable + ')';
    }
    readout.textContent = text;
    readout.className = frame && frame.tensions && frame.tensions.held ? '' : 'refused';
    window.pkmView.tensions = text;
  }

  // A small x y z cross in the corner, turned as the machine is.
  function drawAxes(g) {
    var cy = Math.cos(view.yaw), sy = Math.sin(view.yaw);
    var cp = Math.cos(view.pitch), sp = Math.sin(view.pitch);
    var ox = 40, oy = scene.height - 40, L = 26;
    [[1, 0, 0, 'x', '#c0392b'], [0, 1, 0, 'y', '#27ae60'], [0, 0, 1, 'z', '#2a6fdb']]
        .forEach(function (a) {
          var rx = cy * a[0] - sy * a[1], ry = sy * a[0] + cy * a[1];
          var px = ox + rx * L, py = oy - (a[2] * cp + ry * sp) * L;
          g.strokeStyle = a[4];
          g.lineWidth = 2;
          g.beginPath();
          g.moveTo(ox, oy);
          g.lineTo(px, py);
          g.stroke();
          g.fillStyle = a[4];
          g.fillText(a[3], px + 3, py - 3);
        });
  }

  function legend() {
    var c = data.colour;
    if (data.cells) {
      document.getElementById('legend').textContent =
          'green: inside, orange: boundary (undecided), blue: largest box, black: largest cylinder';
    } else if (!c) {
      document.getElementById('legend').style.display = 'none';
    }
    if (!c) return;
    document.getElementById('legend-label').textContent = c.label + ' 0';
    document.getElementById('legend-max').textContent = short(cMax) + ' ' + c.unit;
    var bar = document.getElementById('legend-bar'), g = bar.getContext('2d');
    for (var x = 0; x < bar.width; ++x) {
      g.fillStyle = rampColour(x / (bar.width - 1));
      g.fillRect(x, 0, 1, bar.height);
    }
    document.getElementById('scene-help').textContent =
        (data.job_outline ? 'grey: the job the blocks must trace; dots: block ends. ' : '') +
        (planar ? 'drag: move, wheel: zoom, double-click: reset' :
                  'drag: turn, shift-drag: move, wheel: zoom, double-click: reset');
  }

  function sceneInput() {
    var dragging = null;
    scene.addEventListener('mousedown', function (e) {
      dragging = {x: e.clientX, y: e.clientY, shift: e.shiftKey || planar};
    });
    window.addEventListener('mouseup', function () { dragging = null; });
    window.addEventListener('mousemove', function (e) {
      if (!dragging) return;
      var dx = e.clientX - dragging.x, dy = e.clientY - dragging.y;
      dragging.x = e.clientX;
      dragging.y = e.clientY;
      var k = scene.width / scene.clientWidth;
      if (dragging.shift) {
        view.panX += dx * k;
        view.panY += dy * k;
      } else {
        view.yaw += dx * 0.01;
        view.pitch = Math.max(-1.5, Math.min(1.5, view.pitch + dy * 0.01));
      }
      requestDraw();
    });
    scene.addEventListener('wheel', function (e) {
      e.preventDefault();
      view.zoom *= Math.exp(-e.deltaY * 0.0015);
      requestDraw();
    }, {passive: false});
    scene.addEventListener('dblclick', function () {
      view = {yaw: -0.6, pitch: 0.45, zoom: 1, panX: 0, panY: 0};
      requestDraw();
    });
  }

  // ---- charts ----
  var charts = data.charts;
  var jointSelect = document.getElementById('joint');
  var chartCanvases = [];

  function chartSetup() {
    if (!charts) { document.getElementById('charts-panel').style.display = 'none'; return; }
    (data.joints || []).forEach(function (j, i) {
      var o = el('option', j.name);
      o.value = String(i);
      jointSelect.appendChild(o);
    });
    jointSelect.value = String(Math.max(0, data.worst_joint_index || 0));
    jointSelect.addEventListener('change', requestDraw);
    var box = document.getElementById('charts');
    charts.quantities.forEach(function () {
      var div = el('div', undefined, 'chart'), c = el('canvas');
      c.width = 560;
      c.height = 200;
      div.appendChild(c);
      box.appendChild(div);
      chartCanvases.push(c);
    });
  }

  function seriesOf(q) {
    return q.series.length === 1 ? q.series[0] : q.series[+jointSelect.value] || q.series[0];
  }

  function unitOf(q) {
    if (q.unit) return q.unit;
    var j = (data.joints || [])[+jointSelect.value] || {unit: ''};
    return j.unit + ['', '/s', '/s^2'][q.per_s || 0];
  }

  function drawChart(canvas, q) {
    if (canvas.clientWidth > 0 && canvas.width !== canvas.clientWidth) {
      canvas.width = canvas.clientWidth;  // drawn at the size shown, text unstretched
    }
    var g = canvas.getContext('2d'), w = canvas.width, h = canvas.height;
    var s = seriesOf(q), xs = charts.x, n = s.min.length;
    var left = 64, right = 10, top = 22, bottom = 36;  // the axis's name on a line of its own
    g.fillStyle = '#fff';
    g.fillRect(0, 0, w, h);
    // Padded by 2 % on each side, so that a peak at either end is not hidden in the frame.
    var x0 = xs.first[0], x1 = xs.last[n - 1];
    if (!(x1 > x0)) { x0 -= 0.5; x1 += 0.5; }
    var xpad = 0.02 * (x1 - x0);
    x0 -= xpad; x1 += xpad;
    var lo = Infinity, hi = -Infinity;
    for (var i = 0; i < n; ++i) {
      if (s.min[i] !== null) lo = Math.min(lo, s.min[i]);
      if (s.max[i] !== null) hi = Math.max(hi, s.max[i]);
    }
    [s.lo, s.hi].forEach(function (v) {
      if (v !== null && isFinite(v)) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
    });
    if (s.lo === null) lo = Math.min(lo, 0);  // one-sided bands (deviation) start at zero
    if (!isFinite(lo)) { lo = 0; hi = 1; }
    if (hi - lo < 1e-12) { hi += 0.5; lo -= 0.5; }
    var pad = 0.06 * (hi - lo);
    lo -= pad; hi += pad;
    function X(x) { return left + (x - x0) / (x1 - x0) * (w - left - right); }
    function Y(y) { return top + (hi - y) / (hi - lo) * (h - top - bottom); }
    // Limit bands: what lies beyond a limit is shaded red.
    g.fillStyle = 'rgba(214, 69, 65, 0.14)';
    if (s.hi !== null) g.fillRect(left, top, w - left - right, Math.max(0, Y(s.hi) - top));
    if (s.lo !== null) g.fillRect(left, Y(s.lo), w - left - right, Math.max(0, h - bottom - Y(s.lo)));
    g.strokeStyle = 'rgba(214, 69, 65, 0.7)';
    g.lineWidth = 1;
    [s.lo, s.hi].forEach(function (v) {
      if (v === null) return;
      g.beginPath(); g.moveTo(left, Y(v)); g.lineTo(w - right, Y(v)); g.stroke();
    });
    envelope(g, s, xs, X, Y);
    axes(g, w, h, left, right, top, bottom, x0 + xpad, x1 - xpad, lo + pad, hi - pad, X, Y);
    var name = q.series.length === 1 ? '' : ' of ' + ((data.joints[+jointSelect.value] || {}).name || '');
    g.fillStyle = '#1d2330';
    g.font = '13px system-ui, sans-serif';
    g.fillText(q.name + name + ' (' + unitOf(q) + ')', left, 15);
    var cx = X(currentT);
    g.strokeStyle = '#1d2330';
    g.setLineDash([3, 3]);
    g.beginPath(); g.moveTo(cx, top); g.lineTo(cx, h - bottom); g.stroke();
    g.setLineDash([]);
  }

  // The min/max envelope of each bucket: a band that keeps every peak however many samples a
  // pixel stands for; a gap where a bucket has no value.
  function envelope(g, s, xs, X, Y) {
    g.fillStyle = 'rgba(42, 111, 219, 0.35)';
    g.strokeStyle = '#2a6fdb';
    g.lineWidth = 1.2;
    var n = s.min.length, i = 0;
    while (i < n) {
      while (i < n && s.min[i] === null) ++i;
      var start = i;
      while (i < n && s.min[i] !== null) ++i;
      if (i === start) continue;
      g.beginPath();
      for (var a = start; a < i; ++a) {
        g.lineTo(X(xs.first[a]), Y(s.max[a]));
        g.lineTo(X(xs.last[a]), Y(s.max[a]));
      }
      for (var b = i - 1; b >= start; --b) {
        g.lineTo(X(xs.last[b]), Y(s.min[b]));
        g.lineTo(X(xs.first[b]), Y(s.min[b]));
      }
      g.closePath();
      g.fill();
      g.stroke();
    }
  }

  function axes(g, w, h, left, right, top, bottom, x0, x1, lo, hi, X, Y) {
    g.strokeStyle = '#9aa1ad';
    g.lineWidth = 1;
    g.strokeRect(left, top, w - left - right, h - top - bottom);
    g.fillStyle = '#4a5160';
    g.font = '11px system-ui, sans-serif';
    g.textAlign = 'right';
    [lo, (lo + hi) / 2, hi].forEach(function (v) { g.fillText(short(v), left - 4, Y(v) + 4); });
    [['left', x0], ['center', (x0 + x1) / 2], ['right', x1]].forEach(function (a) {
      g.textAlign = a[0];
      g.fillText(short(a[1]), X(a[1]), h - bottom + 14);
    });
    g.textAlign = 'center';
    g.fillText(charts.x.label + ' (' + charts.x.unit + ')', (left + w - right) / 2, h - 5);
    g.textAlign = 'left';
  }

  // ---- slider ----
  var slider = document.getElementById('slider');
  function setT(t) {
    currentT = Math.max(tRange[0], Math.min(tRange[1], t));
    slider.value = String(Math.round((currentT - tRange[0]) / (tRange[1] - tRange[0]) * 10000));
    requestDraw();
  }
  function sliderSetup() {
    var ts = path.t.length ? path.t : drawing.t;
    if (ts.length) tRange = [ts[0], ts[ts.length - 1]];
    if (!(tRange[1] > tRange[0])) tRange[1] = tRange[0] + 1;
    currentT = tRange[0];
    if (!data.slider) { document.getElementById('slider-row').style.display = 'none'; return; }
    slider.addEventListener('input', function () {
      currentT = tRange[0] + (tRange[1] - tRange[0]) * (+slider.value / 10000);
      requestDraw();
    });
    var fit = document.getElementById('fit');
    if (!path.x.length) fit.style.display = 'none';
    fit.addEventListener('click', function () {
      fitPath = !fitPath;
      fit.textContent = fitPath ? 'whole machine' : 'zoom to the path';
      bounds = sceneBounds();
      view.zoom = 1; view.panX = 0; view.panY = 0;
      pathLayerKey = '';
      requestDraw();
    });
    var playing = null, button = document.getElementById('play');
    button.addEventListener('click', function () {
      if (playing) { clearInterval(playing); playing = null; button.textContent = 'play'; return; }
      button.textContent = 'pause';
      playing = setInterval(function () {
        var next = +slider.value + 10;
        if (next > 10000) next = 0;
        slider.value = String(next);
        currentT = tRange[0] + (tRange[1] - tRange[0]) * (next / 10000);
        requestDraw();
      }, 30);
    });
  }

  var pending = false;
  function requestDraw() {
    if (pending) return;
    pending = true;
    requestAnimationFrame(function () { pending = false; drawAll(); });
  }
  function drawAll() {
    drawScene();
    if (charts) chartCanvases.forEach(function (c, i) { drawChart(c, charts.quantities[i]); });
    if (data.slider) {
      document.getElementById('slider-value').textContent =
          data.slider.label + ' ' + short(currentT) + ' ' + data.slider.unit;
    }
    window.pkmView.frames += 1;
  }

  // ---- workspace maps: one image per map, null (unreachable) left grey ----
  function drawMaps() {
    var panel = document.getElementById('maps-panel');
    (data.maps || []).forEach(function (m) {
      var nx = m.dims[0], ny = m.dims[1], lo = Infinity, hi = -Infinity;
      m.values.forEach(function (v) {
        if (v !== null) { lo = Math.min(lo, v); hi = Math.max(hi, v); }
      });
      if (!isFinite(lo)) { lo = 0; hi = 1; }
      // A map equal everywhere but for rounding (a hexapod's or cable machine's joint speed per
      // tool speed is 1 at every point) is one colour, not its rounding noise spread on the ramp.
      var constant = hi - lo <= 1e-9 * Math.max(Math.abs(lo), Math.abs(hi));
      var box = el('div', undefined, 'map');
      box.appendChild(el('h2', m.name.replace(/_/g, ' ') + ' (plane ' + m.plane + ' = ' +
                                short(m.at_mm) + ' mm)'));
      var canvas = el('canvas');
      var k = Math.max(1, Math.floor(320 / Math.max(nx, ny)));
      canvas.width = nx * k;
      canvas.height = ny * k;
      canvas.className = 'map-image';
      var g = canvas.getContext('2d');
      for (var j = 0; j < ny; ++j) {
        for (var i = 0; i < nx; ++i) {
          var v = m.values[j * nx + i];
          g.fillStyle = v === null ? '#e4e6ea'
                                   : rampColour(constant ? 0.5 : (v - lo) / ((hi - lo) || 1));
          g.fillRect(i * k, (ny - 1 - j) * k, k, k);  // y up
        }
      }
      box.appendChild(canvas);
      var x0 = m.origin_mm[0], y0 = m.origin_mm[1];
      box.appendChild(el('p', 'x ' + short(x0) + ' to ' + short(x0 + nx * m.step_mm) + ' mm, y ' +
                              short(y0) + ' to ' + short(y0 + ny * m.step_mm) + ' mm (up)'));
      box.appendChild(el('p', constant ? short(lo) + ' at every reachable point; grey: unreachable'
                                       : 'from ' + short(lo) + ' (blue) to ' + short(hi) +
                                             ' (red); grey: unreachable'));
      panel.appendChild(box);
    });
  }

  window.addEventListener('resize', requestDraw);

  window.pkmView = {ready: false, frames: 0, setT: setT, data: data};
  fillSummary();
  legend();
  sceneInput();
  chartSetup();
  sliderSetup();
  drawMaps();
  drawAll();
  window.pkmView.readyAt = performance.now();  // ms since navigation began: bench/html_views.py
  window.pkmView.ready = true;
})();
