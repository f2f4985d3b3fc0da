(function () {
  'use strict';
  var D = JSON.parse(document.getElementById('vantage-data').textContent);
  var problems = [];
  var C = D.colors;
  var KEEP_OUT = '#e65100';  // keep-out boxes, 3D view and legend
  var ARM = '#5e35b1';       // a camera on an arm: its ghosts, path and time line

  function esc(s) {
    return String(s).replace(/[&<>"']/g, function (c) {
      return {'&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;'}[c];
    });
  }
  function pct(x) { return x === null || x === undefined ? '' : (100 * x).toFixed(2) + ' %'; }
  function fix(x, d) { return x === null || x === undefined ? '' : Number(x).toFixed(d); }
  function css(rgb) { return 'rgb(' + rgb[0] + ',' + rgb[1] + ',' + rgb[2] + ')'; }
  // One colour per method, the same in every report (visualize.hpp, kMethodColors).
  function methodColor(method) { return css(C.methods[method] || C.other_method); }
  function bytes(b64) {
    var bin = atob(b64), out = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; ++i) out[i] = bin.charCodeAt(i);
    return out.buffer;
  }
  // Candidate coverage colour ramp (viridis-like), t in [0, 1] -> [r, g, b] in 0..255.
  var RAMP = [[68, 1, 84], [59, 82, 139], [33, 145, 140], [94, 201, 98], [253, 231, 37]];
  function ramp(t) {
    t = Math.max(0, Math.min(1, t)) * (RAMP.length - 1);
    var i = Math.min(RAMP.length - 2, Math.floor(t)), f = t - i, a = RAMP[i], b = RAMP[i + 1];
    return [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])];
  }
  var covMin = Infinity, covMax = -Infinity;
  D.candidates.forEach(function (c) { covMin = Math.min(covMin, c.coverage); covMax = Math.max(covMax, c.coverage); });
  if (!(covMax > covMin)) { covMin = Math.min(covMin, 0); covMax = Math.max(covMin + 1e-9, covMax); }
  function candidateColor(c) { return ramp((c.coverage - covMin) / (covMax - covMin)); }
  function guarded(name, fn) {
    try { fn(); } catch (e) {
      problems.push(name + ': ' + (e && e.message ? e.message : e));
      if (window.console) console.error(e);
    }
  }

  // ------------------------------------------------------------------ notes
  guarded('notes', function () {
    var ul = document.getElementById('notes');
    D.notes.forEach(function (n) { var li = document.createElement('li'); li.textContent = n; ul.appendChild(li); });
  });

  // ------------------------------------------------------------------ sortable tables
  function makeTable(table, columns, rows, rowClass) {
    var state = {key: null, dir: 1};
    function draw() {
      var sorted = rows.slice();
      if (state.key !== null) {
        var col = columns[state.key];
        sorted.sort(function (a, b) {
          var x = col.value(a), y = col.value(b);
          if (x === y) return 0;
          if (x === null || x === undefined || x === '') return 1;
          if (y === null || y === undefined || y === '') return -1;
          return (col.num ? x - y : String(x).localeCompare(String(y), undefined, {numeric: true})) * state.dir;
        });
      }
      var head = '<thead><tr>' + columns.map(function (c, i) {
        var sort = state.key === i ? (state.dir > 0 ? 'ascending' : 'descending') : 'none';
        return '<th data-i="' + i + '" aria-sort="' + sort + '"' + (c.num ? ' class="num"' : '') +
               ' title="sort by ' + esc(c.label) + '">' + esc(c.label) + '</th>';
      }).join('') + '</tr></thead>';
      var body = '<tbody>' + sorted.map(function (r) {
        var cls = rowClass ? rowClass(r) : '';
        return '<tr' + (cls ? ' class="' + cls + '"' : '') + (r.__id !== undefined ? ' data-id="' + r.__id + '"' : '') + '>' +
          columns.map(function (c) {
            var v = c.value(r);
            return '<td' + (c.num ? ' class="num"' : '') + '>' + esc(c.show ? c.show(v, r) : (v === null || v === undefined ? '' : v)) + '</td>';
          }).join('') + '</tr>';
      }).join('') + '</tbody>';
      table.innerHTML = head + body;
      Array.prototype.forEach.call(table.querySelectorAll('th'), function (th) {
        th.addEventListener('click', function () {
          var i = Number(th.getAttribute('data-i'));
          state.dir = state.key === i ? -state.dir : (columns[i].num ? -1 : 1);
          state.key = i;
          draw();
        });
      });
    }
    draw();
  }

  var chosenOrder = {};
  D.chosen.forEach(function (s, k) { chosenOrder[s.index] = k + 1; });

  guarded('tables', function () {
    var primary = D.primary;
    document.getElementById('chosen-title').textContent = primary
      ? 'Chosen sensors — ' + primary.method + ', N = ' + primary.n + ', coverage ' + pct(primary.coverage)
      : 'Chosen sensors — no result';
    var chosenRows = D.chosen.map(function (s, k) {
      var c = D.candidates[s.index];
      return {__id: s.index, order: k + 1, name: c.name, type: c.type, x: c.p[0], y: c.p[1], z: c.p[2],
              roll: s.rpy_deg[0], pitch: s.rpy_deg[1], yaw: s.rpy_deg[2],
              q: c.q, coverage: c.coverage, gain: s.marginal_gain, cumulative: s.cumulative};
    });
    makeTable(document.getElementById('chosen-table'), [
      {label: '#', num: true, value: function (r) { return r.order; }},
      {label: 'name', value: function (r) { return r.name; }},
      {label: 'type', value: function (r) { return r.type; }},
      {label: 'x [m]', num: true, value: function (r) { return r.x; }, show: function (v) { return fix(v, 4); }},
      {label: 'y [m]', num: true, value: function (r) { return r.y; }, show: function (v) { return fix(v, 4); }},
      {label: 'z [m]', num: true, value: function (r) { return r.z; }, show: function (v) { return fix(v, 4); }},
      {label: 'roll [°]', num: true, value: function (r) { return r.roll; }, show: function (v) { return fix(v, 2); }},
      {label: 'pitch [°]', num: true, value: function (r) { return r.pitch; }, show: function (v) { return fix(v, 2); }},
      {label: 'yaw [°]', num: true, value: function (r) { return r.yaw; }, show: function (v) { return fix(v, 2); }},
      {label: 'quaternion w x y z', value: function (r) { return r.q.map(function (v) { return v.toFixed(4); }).join(' '); }},
      {label: 'coverage alone', num: true, value: function (r) { return r.coverage; }, show: pct},
      {label: 'marginal gain', num: true, value: function (r) { return r.gain; }, show: pct},
      {label: 'cumulative', num: true, value: function (r) { return r.cumulative; }, show: pct}
    ], chosenRows);

    makeTable(document.getElementById('results-table'), [
      {label: 'method', value: function (r) { return r.method; }},
      {label: 'N', num: true, value: function (r) { return r.n; }},
      {label: 'from', value: function (r) { return r.curve ? 'curve' : 'run'; }},
      {label: 'coverage', num: true, value: function (r) { return r.coverage; }, show: pct},
      {label: 'paper coverage', num: true, value: function (r) { return r.paper_coverage; }, show: pct},
      {label: 'upper bound', num: true, value: function (r) { return r.upper_bound; }, show: pct},
      {label: 'optimal', value: function (r) { return r.upper_bound === undefined ? '' : (r.optimal ? 'yes' : 'no'); }},
      {label: 'seconds', num: true, value: function (r) { return r.seconds; }, show: function (v) { return fix(v, 3); }},
      {label: 'sensors', value: function (r) { return r.sensors.map(function (i) { return D.candidates[i].name; }).join(', '); }}
    ].concat(D.quality && !D.states ? [{label: 'plain coverage (every pixel)', num: true,
                           value: function (r) { return r.plain_coverage; }, show: pct}] : [])
     .concat(D.states ? D.states.names.map(function (name, k) {
       return {label: 'state ' + name, num: true, value: function (r) { return r.state_coverage[k]; }, show: pct};
     }) : [])
     // A budget or --cheapest: what each answer costs.
     .concat(D.results.some(function (r) { return r.cost !== undefined; })
       ? [{label: 'cost', num: true, value: function (r) { return r.cost === undefined ? null : r.cost; },
           show: function (v) { return v === null ? '' : fix(v, 2); }}] : []), D.results.concat(D.curve.map(function (r) {
       var row = {curve: true}; for (var key in r) row[key] = r[key];
       return row;
     })));

    // optimize --by-type (issue 43): the best constellation of each sensor type alone at every N,
    // then the run's best over all types (the mix) with its gain over the best single type.
    if (D.by_type) {
      document.getElementById('by-type-title').hidden = false;
      var byTypeText = document.getElementById('by-type-text');
      byTypeText.hidden = false;
      byTypeText.textContent = 'Each sensor type alone, chosen by the run\'s own selection at every N, ' +
        'and the mix of all types; gain: what the mix covers beyond the best single type at that N.';
      var typeRows = [];
      D.by_type.types.forEach(function (t) {
        t.best.forEach(function (b) {
          // A type the physical model sees as the ideal pinhole says so (issue 43).
          typeRows.push({type: t.type + (t.physical_model ? ' (physical model ' + t.physical_model + ')' : ''), n: b.n, coverage: b.coverage, upper_bound: b.upper_bound,
                         optimal: b.optimal, candidates: t.candidates, unit_cost: t.unit_cost,
                         total_cost: b.total_cost, gain: null, sensors: b.sensors.join(', ')});
        });
      });
      D.by_type.mix.forEach(function (m) {
        typeRows.push({type: 'mix: ' + m.types.join(' + '), n: m.n, coverage: m.coverage,
                       upper_bound: m.upper_bound, optimal: m.optimal, candidates: null,
                       unit_cost: null, total_cost: m.total_cost, gain: m.gain,
                       sensors: m.sensors.join(', ')});
      });
      makeTable(document.getElementById('by-type-table'), [
        {label: 'type', value: function (r) { return r.type; }},
        {label: 'N', num: true, value: function (r) { return r.n; }},
        {label: 'coverage', num: true, value: function (r) { return r.coverage; }, show: pct},
        {label: 'upper bound', num: true, value: function (r) { return r.upper_bound; }, show: pct},
        {label: 'optimal', value: function (r) { return r.optimal ? 'yes' : 'no'; }},
        {label: 'candidates', num: true, value: function (r) { return r.candidates; }},
        {label: 'unit cost', num: true, value: function (r) { return r.unit_cost; }},
        {label: 'total cost', num: true, value: function (r) { return r.total_cost; }},
        {label: 'gain of the mix', num: true, value: function (r) { return r.gain; }, show: pct},
        {label: 'sensors', value: function (r) { return r.sensors; }}
      ], typeRows);
    }

    // What all candidates reach together, each target part (for the primary result and the
    // ceiling), and the mounting tolerance: report.json's entries (issue 46).
    var A = D.answers || {};
    if (!A.ceiling) {
      document.getElementById('ceiling-text').textContent = D.states
        ? 'Over scene states each result counts per state (see the results): no single ceiling.'
        : 'Not computed for this run.';
    } else {
      var cl = A.ceiling;
      var ct = 'All ' + cl.candidates + ' candidates together reach ' + pct(cl.coverage) + ' (the ceiling).';
      if (cl.unexposed !== undefined)
        ct += ' ' + pct(cl.unexposed) + ' of the target surface is unexposed (resting on or enclosed by other ' +
              'geometry, found from the geometry alone): no layout can exceed ' + pct(1 - cl.unexposed) + '.';
      else if (cl.exposed_only)
        ct += ' Only exposed surface counts (--exposed-only): ' + cl.left_out_voxels +
              ' unexposed voxels are left out of the reference.';
      var primaryParts = D.primary ? A.part_coverage[D.primary.index] : null;
      if (primaryParts) ct += ' Each part, for ' + D.primary.method + ' N = ' + D.primary.n + ' and for the ceiling:';
      document.getElementById('ceiling-text').textContent = ct;
      var partColumns = [
        {label: 'part', value: function (r) { return r.name; }},
        {label: 'voxels', num: true, value: function (r) { return r.voxels; }}];
      if (cl.unexposed !== undefined)
        partColumns.push({label: 'unexposed voxels', num: true, value: function (r) { return r.unexposed_voxels; }});
      if (primaryParts)
        partColumns.push({label: 'this run', num: true, value: function (r) { return primaryParts[r.name]; }, show: pct});
      partColumns.push({label: 'ceiling', num: true, value: function (r) { return r.coverage; }, show: pct});
      makeTable(document.getElementById('parts-table'), partColumns, cl.parts);
    }
    if (A.pose_tolerance) {
      var pt = A.pose_tolerance;
      ['tolerance-title', 'tolerance-text'].forEach(function (id) { document.getElementById(id).hidden = false; });
      document.getElementById('tolerance-text').textContent =
        'Coverage of ' + pt.samples + ' layouts per result with every sensor moved up to ' + pt.position_m +
        ' m and turned up to ' + pt.angle_deg + '° (seeded): mean, 5th percentile and worst, and the sensor ' +
        'whose error costs most.';
      makeTable(document.getElementById('tolerance-table'), [
        {label: 'result', value: function (r) { var x = D.results[r.result]; return x.method + ' N = ' + x.n; }},
        {label: 'planned', num: true, value: function (r) { return r.nominal; }, show: pct},
        {label: 'mean', num: true, value: function (r) { return r.mean; }, show: pct},
        {label: '5th percentile', num: true, value: function (r) { return r.p5; }, show: pct},
        {label: 'worst', num: true, value: function (r) { return r.worst; }, show: pct},
        {label: 'costliest sensor', value: function (r) { return r.costliest_sensor || ''; }}
      ], pt.results);
    }

    // Robustness of the primary result: each sensor failing, the narrower fields of view and
    // one-sensor alternatives.
    var rb = D.robustness;
    if (!rb) {
      document.getElementById('robustness-text').textContent = D.states
        ? 'Not computed over scene states (the read-outs are per constellation of one scene).'
        : 'Not computed for this run.';
    } else {
      var base = D.results[rb.result];
      var text = 'For ' + base.method + ', N = ' + base.n + ' (' + pct(base.coverage) + ').';
      if (rb.fov_shrunk_coverage !== undefined)
        text += ' With every field of view ' + rb.fov_tolerance_deg + '° narrower: ' + pct(rb.fov_shrunk_coverage) +
                ' (a narrower field of view can also raise coverage: the same pixels, denser).';
      else if (rb.fov_note) text += ' ' + rb.fov_note + '.';
      // With one sensor its failure leaves nothing: that row would say nothing.
      if (base.n < 2) text += ' Sensor failures are not listed for one sensor.';
      document.getElementById('robustness-text').textContent = text;
      var rows = rb.sensor_failures.filter(function () { return base.n >= 2; }).map(function (f) {
        return {what: 'fails', sensor: f.sensor, other: '', coverage: f.coverage, change: f.coverage - base.coverage};
      }).concat(rb.alternatives.map(function (a) {
        return {what: 'replaced by', sensor: a.replaced, other: a.replacement, coverage: a.coverage, change: a.coverage - base.coverage,
                cost: a.cost};
      }));
      var robustnessColumns = [
        {label: 'sensor', value: function (r) { return r.sensor; }},
        {label: 'event', value: function (r) { return r.what; }},
        {label: 'replacement', value: function (r) { return r.other; }},
        {label: 'coverage', num: true, value: function (r) { return r.coverage; }, show: pct},
        {label: 'change [points]', num: true, value: function (r) { return 100 * r.change; }, show: function (v) { return fix(v, 2); }}
      ];
      // A priced result (a budget, --cheapest): what each alternative costs beside its own cost.
      if (base.cost !== undefined && base.cost !== null)
        robustnessColumns.push({label: 'cost (this: ' + fix(base.cost, 2) + ')', num: true,
                                value: function (r) { return r.cost === undefined ? null : r.cost; },
                                show: function (v) { return v === null ? '' : fix(v, 2); }});
      makeTable(document.getElementById('robustness-table'), robustnessColumns, rows);
    }

    document.getElementById('candidates-title').textContent = 'Candidates (' + D.candidates.length + ')';
    var candidateRows = D.candidates.map(function (c, i) {
      return {__id: i, index: i, name: c.name, type: c.type, population: c.population, x: c.p[0], y: c.p[1], z: c.p[2],
              coverage: c.coverage, paper: c.paper_coverage, observed: c.observed, near: c.near, far: c.far,
              res: c.w + '×' + c.h, chosen: chosenOrder[i] || null};
    });
    makeTable(document.getElementById('candidates-table'), [
      {label: 'index', num: true, value: function (r) { return r.index; }},
      {label: 'name', value: function (r) { return r.name; }},
      {label: 'type', value: function (r) { return r.type; }},
      {label: 'population', value: function (r) { return r.population; }},
      {label: 'x [m]', num: true, value: function (r) { return r.x; }, show: function (v) { return fix(v, 4); }},
      {label: 'y [m]', num: true, value: function (r) { return r.y; }, show: function (v) { return fix(v, 4); }},
      {label: 'z [m]', num: true, value: function (r) { return r.z; }, show: function (v) { return fix(v, 4); }},
      {label: 'resolution', value: function (r) { return r.res; }},
      {label: 'near–far [m]', value: function (r) { return r.near + '–' + r.far; }},
      {label: 'observed voxels', num: true, value: function (r) { return r.observed; }},
      {label: 'coverage', num: true, value: function (r) { return r.coverage; }, show: pct},
      {label: 'paper coverage', num: true, value: function (r) { return r.paper; }, show: pct},
      {label: 'chosen', num: true, value: function (r) { return r.chosen; }}
    ], candidateRows, function (r) { return r.chosen ? 'chosen' : ''; });
  });

  // ------------------------------------------------------------------ the arm's tour
  // A camera on an arm (docs/arm.md): the primary result's tour as a time line — each move (grey;
  // hatched when planned around a collision) and each view's acquisition (the arm's colour),
  // home to home, on one axis of seconds.
  guarded('tour', function () {
    if (!D.arm || !D.arm.stops.length) return;
    var SVG = 'http://www.w3.org/2000/svg';
    function node(name, attrs, parent, text) {
      var e = document.createElementNS(SVG, name);
      for (var k in attrs) e.setAttribute(k, attrs[k]);
      if (text !== undefined) e.textContent = text;
      if (parent) parent.appendChild(e);
      return e;
    }
    var stops = D.arm.stops, t = 0, spans = [];
    stops.forEach(function (s, k) {
      var move = s.move_seconds === null ? NaN : s.move_seconds;
      spans.push({kind: 'move', from: t, to: t + move, planned: s.planned, label: s.name});
      t += move;
      spans.push({kind: 'view', from: t, to: t + s.acquisition_seconds, label: (k + 1) + ' ' + s.name + (s.state ? ' (' + s.state + ')' : '')});
      t += s.acquisition_seconds;
    });
    var back = D.arm.return_seconds === null ? NaN : D.arm.return_seconds;
    spans.push({kind: 'move', from: t, to: t + back, planned: false, label: 'home'});
    t += back;
    document.getElementById('tour-title').hidden = false;
    var text = document.getElementById('tour-text');
    text.hidden = false;
    text.textContent = 'Robot ' + D.arm.robot + ': ' + stops.length + ' views, ' +
      (isFinite(t) ? t.toFixed(2) + ' s of motion and acquisition from home back to home' : 'some move is not connected') +
      ' (order: ' + D.arm.method + (D.arm.exact ? ', exact' : '') + ').' +
      (D.arm.seconds !== null && isFinite(t) && Math.abs(D.arm.seconds - t) > 1e-6 ? ' With the states\' spacing: ' + D.arm.seconds.toFixed(2) + ' s.' : '');
    if (!isFinite(t) || t <= 0) return;
    var W = 760, L = 16, R = 16, rowH = 18, T = 8, H = T + stops.length * rowH + 40;
    var svg = node('svg', {id: 'tour-line', viewBox: '0 0 ' + W + ' ' + H, width: W, height: H, role: 'img',
                           'aria-label': 'the arm tour time line'}, document.getElementById('tour-box'));
    var X = function (s) { return L + (W - L - R) * s / t; };
    var axisY = T + stops.length * rowH + 6;
    var row = 0;
    spans.forEach(function (span) {
      var y = span.kind === 'view' ? T + (row++) * rowH : axisY - 12;
      var w = Math.max(1, X(span.to) - X(span.from));
      var rect = node('rect', {x: X(span.from), y: y, width: w, height: span.kind === 'view' ? rowH - 4 : 10,
                               fill: span.kind === 'view' ? ARM : (span.planned ? '#9e9e9e' : '#cfd3da'),
                               stroke: span.planned ? '#424242' : 'none', 'stroke-dasharray': span.planned ? '3 2' : ''}, svg);
      node('title', {}, rect, (span.kind === 'view' ? 'acquisition at ' : 'move to ') + span.label + ': ' +
           span.from.toFixed(2) + '–' + span.to.toFixed(2) + ' s');
      if (span.kind === 'view') {
        var right = X(span.to) + 4 < W - 200;
        node('text', {x: right ? X(span.to) + 4 : X(span.from) - 4, y: y + rowH - 8, 'font-size': 11,
                      'text-anchor': right ? 'start' : 'end'}, svg, span.label + ' @ ' + span.from.toFixed(2) + ' s');
        node('line', {x1: X(span.from), x2: X(span.from), y1: y + rowH - 4, y2: axisY - 2, stroke: ARM, 'stroke-width': 0.5}, svg);
      }
    });
    node('line', {x1: L, x2: W - R, y1: axisY, y2: axisY, stroke: '#555'}, svg);
    for (var k = 0; k <= 5; ++k) {
      var s = t * k / 5;
      node('text', {x: X(s), y: axisY + 14, 'font-size': 11, 'text-anchor': k === 0 ? 'start' : k === 5 ? 'end' : 'middle'},
           svg, s.toFixed(1) + ' s');
    }
    node('text', {x: L, y: axisY + 30, 'font-size': 11}, svg,
         'grey: moves (dashed: planned around a collision); coloured: acquisition at each view; home at 0 s and at the end');
  });

  // ------------------------------------------------------------------ chart
  guarded('chart', function () {
    var SVG = 'http://www.w3.org/2000/svg';
    var W = 760, H = 340, L = 56, R = 200, T = 16, B = 44;
    // The run's results and the curve's extra answers (report.json `curve`, drawn hollow): every
    // point drawn is an entry of report.json.
    var series = {}, order = [];
    var points = D.results.concat(D.curve.map(function (r) {
      var copy = {}; for (var key in r) copy[key] = r[key];
      copy.curve = true;
      return copy;
    }));
    points.forEach(function (r) {
      if (!series[r.method]) { series[r.method] = []; order.push(r.method); }
      series[r.method].push(r);
    });
    var maxN = 1, maxY = 0;
    points.forEach(function (r) {
      maxN = Math.max(maxN, r.n);
      maxY = Math.max(maxY, r.coverage, r.upper_bound === undefined ? 0 : r.upper_bound);
    });
    var tick = maxY > 0.5 ? 0.1 : (maxY > 0.2 ? 0.05 : 0.02);
    maxY = Math.min(1, Math.max(tick, Math.ceil(maxY / tick + 0.001) * tick));
    function X(n) { return maxN === 1 ? L + (W - L - R) / 2 : L + (n - 1) / (maxN - 1) * (W - L - R); }
    function Y(v) { return T + (1 - v / maxY) * (H - T - B); }
    function el(name, attrs, parent, text) {
      var e = document.createElementNS(SVG, name);
      for (var k in attrs) e.setAttribute(k, attrs[k]);
      if (text !== undefined) e.textContent = text;
      if (parent) parent.appendChild(e);
      return e;
    }
    var svg = el('svg', {id: 'chart', viewBox: '0 0 ' + W + ' ' + H, width: W, height: H, role: 'img',
                         'aria-label': 'coverage versus number of sensors'});
    var grid = el('g', {'class': 'axes'}, svg);
    for (var k = 0; k * tick <= maxY + 1e-9; ++k) {
      var v = k * tick;
      el('line', {x1: L, x2: W - R, y1: Y(v), y2: Y(v), stroke: '#e3e7ec'}, grid);
      el('text', {x: L - 6, y: Y(v) + 4, 'text-anchor': 'end', fill: '#5d6875'}, grid, (100 * v).toFixed(0) + ' %');
    }
    var step = Math.max(1, Math.ceil(maxN / 12));
    for (var n = 1; n <= maxN; n += step) {
      el('line', {x1: X(n), x2: X(n), y1: H - B, y2: H - B + 4, stroke: '#5d6875'}, grid);
      el('text', {x: X(n), y: H - B + 17, 'text-anchor': 'middle', fill: '#5d6875'}, grid, n);
    }
    el('line', {x1: L, x2: W - R, y1: H - B, y2: H - B, stroke: '#5d6875'}, grid);
    el('line', {x1: L, x2: L, y1: T, y2: H - B, stroke: '#5d6875'}, grid);
    el('text', {x: (L + W - R) / 2, y: H - 8, 'text-anchor': 'middle', fill: '#1d232b'}, grid, 'number of sensors N');
    el('text', {x: 14, y: (T + H - B) / 2, 'text-anchor': 'middle', fill: '#1d232b',
                transform: 'rotate(-90 14 ' + (T + H - B) / 2 + ')'}, grid, 'coverage');
    // The run's N.
    if (D.primary) {
      el('line', {x1: X(D.primary.n), x2: X(D.primary.n), y1: T, y2: H - B, stroke: '#1d232b',
                  'stroke-width': 1, 'stroke-dasharray': '3 3', 'class': 'run-n'}, grid);
      el('text', {x: X(D.primary.n) + (D.primary.n === maxN ? -4 : 4), y: T + 10, fill: '#1d232b',
                  'text-anchor': D.primary.n === maxN ? 'end' : 'start'}, grid, 'this run: N = ' + D.primary.n);
    }
    order.forEach(function (method, m) {
      var color = methodColor(method);
      var pts = series[method].slice().sort(function (a, b) { return a.n - b.n; });
      var g = el('g', {'class': 'series', 'data-method': method}, svg);
      if (pts.length > 1)
        el('polyline', {points: pts.map(function (r) { return X(r.n) + ',' + Y(r.coverage); }).join(' '),
                        fill: 'none', stroke: color, 'stroke-width': 2}, g);
      pts.forEach(function (r) {
        var c = el('circle', {cx: X(r.n), cy: Y(r.coverage), r: 4, fill: r.curve ? '#fff' : color,
                              stroke: color, 'stroke-width': 1.5}, g);
        el('title', {}, c, method + ', N = ' + r.n + ': ' + pct(r.coverage) + (r.curve ? ' (computed for the curve)' : ''));
      });
      var bounds = pts.filter(function (r) { return r.upper_bound !== undefined; });
      if (bounds.length) {
        if (bounds.length > 1)
          el('polyline', {points: bounds.map(function (r) { return X(r.n) + ',' + Y(r.upper_bound); }).join(' '),
                          fill: 'none', stroke: color, 'stroke-width': 1.5, 'stroke-dasharray': '5 4'}, g);
        bounds.forEach(function (r) {
          var x = X(r.n), y = Y(r.upper_bound);
          var d = el('path', {d: 'M' + x + ' ' + (y - 5) + 'L' + (x + 5) + ' ' + y + 'L' + x + ' ' + (y + 5) + 'L' + (x - 5) + ' ' + y + 'Z',
                              fill: '#fff', stroke: color, 'stroke-width': 1.5}, g);
          el('title', {}, d, method + ', N = ' + r.n + ': upper bound ' + pct(r.upper_bound) + (r.optimal ? ' (optimal)' : ''));
        });
      }
      var ly = T + 8 + m * 20;
      el('line', {x1: W - R + 14, x2: W - R + 38, y1: ly, y2: ly, stroke: color, 'stroke-width': 2}, svg);
      el('circle', {cx: W - R + 26, cy: ly, r: 4, fill: color}, svg);
      el('text', {x: W - R + 44, y: ly + 4, fill: '#1d232b'}, svg, method + (bounds.length ? ' (◇ bound)' : ''));
    });
    // The primary result's coverage after each of its sensors, in the order chosen.
    if (D.chosen.length > 1) {
      var cum = el('g', {'class': 'cumulative'}, svg);
      el('polyline', {points: D.chosen.map(function (s, k) { return X(k + 1) + ',' + Y(s.cumulative); }).join(' '),
                      fill: 'none', stroke: '#5d6875', 'stroke-width': 1.5, 'stroke-dasharray': '2 3'}, cum);
      D.chosen.forEach(function (s, k) {
        var r = el('rect', {x: X(k + 1) - 3, y: Y(s.cumulative) - 3, width: 6, height: 6, fill: '#5d6875'}, cum);
        el('title', {}, r, 'primary result, first ' + (k + 1) + ' sensor' + (k ? 's' : '') + ' in the order chosen: ' + pct(s.cumulative));
      });
      var cy = T + 8 + order.length * 20;
      order.push('');  // the legend's next row
      el('line', {x1: W - R + 14, x2: W - R + 38, y1: cy, y2: cy, stroke: '#5d6875', 'stroke-width': 1.5,
                  'stroke-dasharray': '2 3'}, svg);
      el('text', {x: W - R + 44, y: cy + 4, fill: '#1d232b'}, svg, 'primary, in order chosen');
    }
    if (D.curve.length) {
      var hy = T + 8 + order.length * 20;
      el('circle', {cx: W - R + 26, cy: hy, r: 4, fill: '#fff', stroke: '#5d6875', 'stroke-width': 1.5}, svg);
      el('text', {x: W - R + 44, y: hy + 4, fill: '#1d232b'}, svg, 'computed for the curve');
    }
    if (!D.results.length) el('text', {x: (L + W - R) / 2, y: (T + H - B) / 2, 'text-anchor': 'middle'}, svg, 'no results');
    document.getElementById('chart-box').appendChild(svg);
  });

  // ------------------------------------------------------------------ coverage versus seconds
  // A camera on an arm (docs/arm.md): each answer (results filled, the curve's hollow) at its
  // tour's time, home to home with acquisition; a method's answers joined in order of N;
  // --cycle-time as a dashed line.
  guarded('seconds-chart', function () {
    var points = D.results.concat(D.curve.map(function (r) {
      var copy = {}; for (var key in r) copy[key] = r[key];
      copy.curve = true;
      return copy;
    })).filter(function (r) { return r.tour_seconds !== undefined; });
    if (!points.length) return;
    var SVG = 'http://www.w3.org/2000/svg';
    var W = 760, H = 300, L = 56, R = 200, T = 16, B = 44;
    function el(name, attrs, parent, text) {
      var e = document.createElementNS(SVG, name);
      for (var k in attrs) e.setAttribute(k, attrs[k]);
      if (text !== undefined) e.textContent = text;
      if (parent) parent.appendChild(e);
      return e;
    }
    var maxT = D.cycle_time === null ? 0 : D.cycle_time, maxY = 0, series = {}, order = [];
    points.forEach(function (r) {
      maxT = Math.max(maxT, r.tour_seconds);
      maxY = Math.max(maxY, r.coverage);
      if (!series[r.method]) { series[r.method] = []; order.push(r.method); }
      series[r.method].push(r);
    });
    // Round steps: 1, 2 or 5 times a power of ten, about five of them.
    function niceStep(span) {
      var raw = Math.max(span, 1e-9) / 5, p = Math.pow(10, Math.floor(Math.log10(raw)));
      return raw <= p ? p : raw <= 2 * p ? 2 * p : raw <= 5 * p ? 5 * p : 10 * p;
    }
    var tStep = niceStep(maxT), yStep = niceStep(maxY);
    maxT = Math.max(tStep, Math.ceil(maxT / tStep - 1e-9) * tStep);
    maxY = Math.min(1, Math.max(yStep, Math.ceil(maxY / yStep + 0.001) * yStep));
    function X(t) { return L + t / maxT * (W - L - R); }
    function Y(v) { return T + (1 - v / maxY) * (H - T - B); }
    var svg = el('svg', {id: 'seconds-chart', viewBox: '0 0 ' + W + ' ' + H, width: W, height: H, role: 'img',
                         'aria-label': 'coverage versus tour seconds'});
    var grid = el('g', {'class': 'axes'}, svg);
    for (var k = 0; k * yStep <= maxY + 1e-9; ++k) {
      var v = k * yStep;
      el('line', {x1: L, x2: W - R, y1: Y(v), y2: Y(v), stroke: '#e3e7ec'}, grid);
      el('text', {x: L - 6, y: Y(v) + 4, 'text-anchor': 'end', fill: '#5d6875'}, grid, (100 * v).toFixed(0) + ' %');
    }
    for (var j = 0; j * tStep <= maxT + 1e-9; ++j) {
      var t = j * tStep;
      el('line', {x1: X(t), x2: X(t), y1: H - B, y2: H - B + 4, stroke: '#5d6875'}, grid);
      el('text', {x: X(t), y: H - B + 17, 'text-anchor': 'middle', fill: '#5d6875'}, grid, +t.toFixed(6) + ' s');
    }
    el('line', {x1: L, x2: W - R, y1: H - B, y2: H - B, stroke: '#5d6875'}, grid);
    el('line', {x1: L, x2: L, y1: T, y2: H - B, stroke: '#5d6875'}, grid);
    el('text', {x: (L + W - R) / 2, y: H - 8, 'text-anchor': 'middle', fill: '#1d232b'}, grid,
       'tour time, home to home with acquisition [s]');
    el('text', {x: 14, y: (T + H - B) / 2, 'text-anchor': 'middle', fill: '#1d232b',
                transform: 'rotate(-90 14 ' + (T + H - B) / 2 + ')'}, grid, 'coverage');
    if (D.cycle_time !== null) {
      el('line', {x1: X(D.cycle_time), x2: X(D.cycle_time), y1: T, y2: H - B, stroke: '#1d232b',
                  'stroke-dasharray': '3 3', 'class': 'cycle-time'}, grid);
      el('text', {x: X(D.cycle_time) - 4, y: T + 10, 'text-anchor': 'end', fill: '#1d232b'}, grid,
         '--cycle-time ' + D.cycle_time + ' s');
    }
    // The most coverage within each time: a step up at each answer that beats every faster one.
    var front = points.slice().sort(function (a, b) { return a.tour_seconds - b.tour_seconds || b.coverage - a.coverage; });
    var steps = [], best = -1;
    front.forEach(function (r) {
      if (r.coverage <= best) return;
      if (steps.length) steps.push(X(r.tour_seconds) + ',' + Y(best));
      steps.push(X(r.tour_seconds) + ',' + Y(r.coverage));
      best = r.coverage;
    });
    steps.push(X(maxT) + ',' + Y(best));
    el('polyline', {points: steps.join(' '), fill: 'none', stroke: '#5d6875', 'stroke-width': 1,
                    'stroke-dasharray': '2 3', 'class': 'front'}, svg);
    var labels = [];  // N labels placed so far: one is skipped where it would overlap another
    order.forEach(function (method, m) {
      var color = methodColor(method);
      var pts = series[method].slice().sort(function (a, b) { return a.n - b.n || a.tour_seconds - b.tour_seconds; });
      var g = el('g', {'class': 'series', 'data-method': method}, svg);
      if (pts.length > 1)
        el('polyline', {points: pts.map(function (r) { return X(r.tour_seconds) + ',' + Y(r.coverage); }).join(' '),
                        fill: 'none', stroke: color, 'stroke-width': 1.5}, g);
      pts.forEach(function (r) {
        var c = el('circle', {cx: X(r.tour_seconds), cy: Y(r.coverage), r: 4, fill: r.curve ? '#fff' : color,
                              stroke: color, 'stroke-width': 1.5}, g);
        el('title', {}, c, method + ', N = ' + r.n + ': ' + pct(r.coverage) + ' in ' + r.tour_seconds.toFixed(2) +
           ' s' + (r.curve ? ' (computed for the curve)' : ''));
        var lx = X(r.tour_seconds) + 6, ly = Y(r.coverage) - 6;
        if (labels.some(function (p) { return Math.abs(p[0] - lx) < 30 && Math.abs(p[1] - ly) < 12; })) return;
        labels.push([lx, ly]);
        el('text', {x: lx, y: ly, fill: color, 'font-size': 10}, g, 'N=' + r.n);
      });
      var ly = T + 8 + m * 20;
      el('line', {x1: W - R + 14, x2: W - R + 38, y1: ly, y2: ly, stroke: color, 'stroke-width': 1.5}, svg);
      el('circle', {cx: W - R + 26, cy: ly, r: 4, fill: color}, svg);
      el('text', {x: W - R + 44, y: ly + 4, fill: '#1d232b'}, svg, method);
    });
    var fy = T + 8 + order.length * 20;
    el('line', {x1: W - R + 14, x2: W - R + 38, y1: fy, y2: fy, stroke: '#5d6875', 'stroke-width': 1,
                'stroke-dasharray': '2 3'}, svg);
    el('text', {x: W - R + 44, y: fy + 4, fill: '#1d232b'}, svg, 'best within the time');
    if (points.some(function (r) { return r.curve; })) {
      el('circle', {cx: W - R + 26, cy: fy + 20, r: 4, fill: '#fff', stroke: '#5d6875', 'stroke-width': 1.5}, svg);
      el('text', {x: W - R + 44, y: fy + 24, fill: '#1d232b'}, svg, 'computed for the curve');
    }
    document.getElementById('seconds-title').hidden = false;
    document.getElementById('seconds-box').appendChild(svg);
  });

  // ------------------------------------------------------------------ what-if model
  // The candidates' observed cells (html_report.cpp, EncodeSets), decoded into one bitset of |R|
  // bits per candidate: the page scores any layout the reader clicks together, as `vantage
  // evaluate` scores it (a cell counts once any sensor of the layout observes it).
  function popcount(x) {
    x -= (x >>> 1) & 0x55555555;
    x = (x & 0x33333333) + ((x >>> 2) & 0x33333333);
    return Math.imul((x + (x >>> 4)) & 0x0F0F0F0F, 0x01010101) >>> 24;
  }
  var WI = null;
  guarded('what-if', function () {
    if (!D.whatif) return;
    var n = D.candidates.length, R = D.whatif.cells, words = (R + 31) >>> 5, setBytes = (R + 7) >>> 3;
    var raw = new Uint8Array(bytes(D.whatif.sets)), at = 0;
    function varint() {
      var value = 0, scale = 1, b;
      do { b = raw[at++]; value += (b & 127) * scale; scale *= 128; } while (b & 128);
      return value;
    }
    var sets = new Uint32Array(n * words), sizes = new Uint32Array(n);
    for (var i = 0; i < n; ++i) {
      var head = varint(), count = Math.floor(head / 2), base = i * words;
      sizes[i] = count;
      if (head % 2) {
        for (var b = 0; b < setBytes; ++b) {
          var v = raw[at + b];
          if (v) sets[base + (b >>> 2)] |= v << ((b & 3) * 8);
        }
        at += setBytes;
      } else {
        for (var k = 0, r = -1; k < count; ++k) {
          r += varint() + 1;
          sets[base + (r >>> 5)] |= 1 << (r & 31);
        }
      }
    }
    if (at !== raw.length) throw new Error('the what-if sets end after ' + at + ' of ' + raw.length + ' bytes');
    var parts = D.whatif.parts || [], cellPart = parts.length ? new Uint16Array(bytes(D.whatif.cell_part)) : null;
    WI = {cells: R, words: words, sets: sets, sizes: sizes, parts: parts, cellPart: cellPart,
          inLayout: new Uint8Array(n), layout: [], covered: new Uint32Array(words), coveredCount: 0,
          seen: new Uint8Array(R), partCovered: new Array(parts.length).fill(0), listeners: []};
    // The layout's union, per-cell counts (the colours) and per-part counts.
    WI.score = function () {
      WI.covered.fill(0);
      WI.seen.fill(0);
      WI.layout.forEach(function (c) {
        var base = c * words;
        for (var w = 0; w < words; ++w) {
          var bits = sets[base + w];
          if (!bits) continue;
          WI.covered[w] |= bits;
          for (; bits; bits &= bits - 1) {
            var cell = (w << 5) + (31 - Math.clz32(bits & -bits));
            if (WI.seen[cell] < 255) ++WI.seen[cell];
          }
        }
      });
      var covered = 0;
      for (var w = 0; w < words; ++w) covered += popcount(WI.covered[w]);
      WI.coveredCount = covered;
      WI.partCovered = new Array(parts.length).fill(0);
      if (cellPart) {
        for (var cell = 0; cell < R; ++cell) {
          if (WI.seen[cell] && cellPart[cell] < parts.length) ++WI.partCovered[cellPart[cell]];
        }
      }
    };
    // Greedy's next step: the candidate outside the layout that adds the most cells (the lowest
    // index among equals, as greedy breaks ties); null when none adds any.
    WI.suggest = function () {
      var best = -1, bestGain = 0;
      for (var c = 0; c < n; ++c) {
        if (WI.inLayout[c] || sizes[c] <= bestGain) continue;
        var gain = 0, base = c * words;
        for (var w = 0; w < words; ++w) {
          var add = sets[base + w] & ~WI.covered[w];
          if (add) gain += popcount(add);
        }
        if (gain > bestGain) { best = c; bestGain = gain; }
      }
      return best < 0 ? null : {index: best, gain: bestGain};
    };
    WI.set = function (indices) {
      WI.inLayout.fill(0);
      WI.layout = [];
      indices.forEach(function (c) { if (!WI.inLayout[c]) { WI.inLayout[c] = 1; WI.layout.push(c); } });
      WI.changed();
    };
    WI.toggle = function (c) {
      if (WI.inLayout[c]) {
        WI.inLayout[c] = 0;
        WI.layout = WI.layout.filter(function (x) { return x !== c; });
      } else {
        WI.inLayout[c] = 1;
        WI.layout.push(c);
      }
      WI.changed();
    };
    WI.changed = function () {
      WI.score();
      WI.listeners.forEach(function (f) { f(); });
    };
    WI.set(D.chosen.map(function (s) { return s.index; }));
  });
  // For scripts driving the page (tests/page/): the layout and its numbers.
  window.vantagePage = {
    layout: function () { return WI ? WI.layout.slice() : null; },
    covered: function () { return WI ? WI.coveredCount : null; },
    cells: function () { return WI ? WI.cells : null; },
    parts: function () {
      return WI ? WI.parts.map(function (p, k) { return {name: p.name, cells: p.cells, covered: WI.partCovered[k]}; }) : null;
    }
  };

  // ------------------------------------------------------------------ what-if panel
  guarded('what-if panel', function () {
    var panel = document.getElementById('whatif');
    if (!WI) {
      panel.style.display = 'none';
      return;
    }
    panel.innerHTML =
      '<div class="head"><b>What if</b> <span class="muted">click a candidate in the view to add or remove it</span></div>' +
      '<div>layout: <span id="whatif-count"></span> · coverage <b id="whatif-coverage"></b></div>' +
      '<div id="whatif-sensors" class="muted"></div>' +
      '<table id="whatif-parts"></table>' +
      '<div id="whatif-next"></div>' +
      '<div class="buttons"><button id="whatif-add" type="button">add it</button> ' +
      '<button id="whatif-reset" type="button">back to the result</button> ' +
      '<button id="whatif-clear" type="button">none</button></div>' +
      '<div id="whatif-last" class="muted"></div>' +
      (D.whatif.note ? '<div class="muted">The what-if ' + esc(D.whatif.note) + '.</div>' : '');
    var next = null;
    function cov(count, total) { return total ? (100 * count / total).toFixed(2) + ' %' : ''; }
    function draw() {
      var total = WI.cells;
      var shown = document.getElementById('whatif-coverage');
      shown.textContent = cov(WI.coveredCount, total);
      shown.setAttribute('data-covered', WI.coveredCount);
      shown.setAttribute('data-cells', total);
      document.getElementById('whatif-count').textContent = WI.layout.length + ' sensor' + (WI.layout.length === 1 ? '' : 's');
      var names = WI.layout.map(function (c) { return D.candidates[c].name; });
      document.getElementById('whatif-sensors').textContent =
        names.length > 6 ? names.slice(0, 5).join(', ') + ' and ' + (names.length - 5) + ' more' : names.join(', ');
      document.getElementById('whatif-parts').innerHTML = WI.parts.length > 1 ? WI.parts.map(function (p, k) {
        return '<tr><td>' + esc(p.name) + '</td><td class="num">' + cov(WI.partCovered[k], p.cells) + '</td></tr>';
      }).join('') : '';
      next = WI.suggest();
      document.getElementById('whatif-next').innerHTML = next
        ? 'best next camera: <b>' + esc(D.candidates[next.index].name) + '</b> +' + cov(next.gain, total).replace(' %', ' points')
        : 'best next camera: none adds a cell';
      document.getElementById('whatif-add').disabled = !next;
    }
    WI.listeners.push(draw);
    document.getElementById('whatif-add').addEventListener('click', function () { if (next) WI.toggle(next.index); });
    document.getElementById('whatif-reset').addEventListener('click', function () {
      WI.set(D.chosen.map(function (s) { return s.index; }));
    });
    document.getElementById('whatif-clear').addEventListener('click', function () { WI.set([]); });
    draw();
  });

  // ------------------------------------------------------------------ 3D view
  function note(text) {
    var div = document.createElement('div');
    div.className = 'note';
    div.textContent = text;
    document.getElementById('view').appendChild(div);
  }

  function build3D() {
    var view = document.getElementById('view');
    var THREE = window.THREE;
    var renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setSize(view.clientWidth, view.clientHeight);
    view.insertBefore(renderer.domElement, view.firstChild);
    var scene = new THREE.Scene();
    scene.background = new THREE.Color(0xeef1f5);
    // The default views (default_view.cpp, FitView): along D.view.direction, far enough that
    // every point lies in the frame with a 5 % margin, for this canvas' aspect.
    function fitView(points, fovDeg, aspect, direction) {
      var d = new THREE.Vector3().fromArray(direction || D.view.direction).normalize();
      var box = new THREE.Box3().setFromPoints(points), centre = box.getCenter(new THREE.Vector3());
      var forward = d.clone().negate(), right = forward.clone().cross(new THREE.Vector3(0, 0, 1));
      if (right.length() < 1e-6) right = forward.clone().cross(new THREE.Vector3(0, 1, 0));
      right.normalize();
      var up = right.clone().cross(forward).normalize();
      var ty = Math.tan(fovDeg * Math.PI / 360), tx = ty * aspect;
      var radius = Math.max(0.5 * box.getSize(new THREE.Vector3()).length(), 1e-3);
      function fit(c) {
        var distance = 0.5 * radius;
        points.forEach(function (p) {
          var v = p.clone().sub(c);
          var lateral = Math.max(Math.abs(v.dot(right)) / tx, Math.abs(v.dot(up)) / ty);
          distance = Math.max(distance, 1.05 * lateral + v.dot(d), v.dot(d) + 0.2 * radius);
        });
        return distance;
      }
      var distance = fit(centre);
      // Centred on the points' extent in the image, twice (as FitView).
      for (var round = 0; round < 2; ++round) {
        var lx = Infinity, hx = -Infinity, ly = Infinity, hy = -Infinity;
        points.forEach(function (p) {
          var v = p.clone().sub(centre), depth = distance - v.dot(d);
          lx = Math.min(lx, v.dot(right) / depth); hx = Math.max(hx, v.dot(right) / depth);
          ly = Math.min(ly, v.dot(up) / depth); hy = Math.max(hy, v.dot(up) / depth);
        });
        var moved = centre.clone().addScaledVector(right, distance * 0.5 * (lx + hx))
                                  .addScaledVector(up, distance * 0.5 * (ly + hy));
        var closer = fit(moved);
        if (closer >= distance) break;
        centre = moved;
        distance = closer;
      }
      return {eye: centre.clone().addScaledVector(d, distance), target: centre, fov: fovDeg};
    }
    var tb = D.view.targets, targetCorners = [];
    for (var corner = 0; corner < 8; ++corner)
      targetCorners.push(new THREE.Vector3(tb[corner & 1 ? 1 : 0][0], tb[corner & 2 ? 1 : 0][1], tb[corner & 4 ? 1 : 0][2]));
    // A camera on an arm: the view frames its links at the views too (their frames' origins).
    var armPoints = [];
    if (D.arm) D.arm.stops.forEach(function (stop) {
      stop.links.forEach(function (p) { armPoints.push(new THREE.Vector3(p[0], p[1], p[2])); });
    });
    var aspect = view.clientWidth / view.clientHeight;
    // A fitted view's make(aspect) frames its points in a picture of that aspect (the part of the
    // canvas the panels leave free: see freeBand); a sensor's own view is not fitted.
    var views = [{name: 'chosen sensors and targets', key: 'sensors', fitted: true,
                  make: function (fitAspect) {
                    return fitView(targetCorners.concat(armPoints, D.view.sensors.map(function (p) { return new THREE.Vector3().fromArray(p); })),
                                   D.view.fov_deg, fitAspect);
                  }},
                 {name: 'targets only', key: 'targets', fitted: true,
                  make: function (fitAspect) { return fitView(targetCorners, D.view.fov_deg, fitAspect); }},
                 // Surface resting on or hidden by other geometry (a part's underside on a
                 // table) is seen from below with the occluders hidden: red where no sensor sees.
                 {name: 'from below, occluders hidden', key: 'below', hide: ['occluders'], fitted: true,
                  make: function (fitAspect) {
                    var d = D.view.direction;
                    return fitView(targetCorners, D.view.fov_deg, fitAspect, [d[0], d[1], -d[2]]);
                  }}];
    // With keep-out boxes, a view that frames them too (their corners, in their poses).
    if (D.keep_out && D.keep_out.length) {
      var boxCorners = [];
      D.keep_out.forEach(function (b) {
        var q = new THREE.Quaternion(b.quaternion[1], b.quaternion[2], b.quaternion[3], b.quaternion[0]);
        for (var corner = 0; corner < 8; ++corner) {
          boxCorners.push(new THREE.Vector3((corner & 1 ? 0.5 : -0.5) * b.size[0], (corner & 2 ? 0.5 : -0.5) * b.size[1],
                                            (corner & 4 ? 0.5 : -0.5) * b.size[2])
            .applyQuaternion(q).add(new THREE.Vector3().fromArray(b.center)));
        }
      });
      views.push({name: 'targets, chosen sensors and keep-out boxes', key: 'keepout', fitted: true, make: function (fitAspect) {
        return fitView(targetCorners.concat(boxCorners, D.view.sensors.map(function (p) { return new THREE.Vector3().fromArray(p); })),
                       D.view.fov_deg, fitAspect);
      }});
    }
    // Each chosen sensor's own view: from its optical centre along its axis, with its vertical
    // field of view (up stays +z: the picture is not rolled as the sensor's image may be).
    D.chosen.forEach(function (s, k) {
      var c = D.candidates[s.index];
      views.push({name: 'from sensor ' + (k + 1) + ': ' + c.name, key: 'sensor' + (k + 1), make: function () {
        var q = new THREE.Quaternion(c.q[1], c.q[2], c.q[3], c.q[0]);
        var apex = new THREE.Vector3().fromArray(c.p);
        var axis = new THREE.Vector3(1, 0, 0).applyQuaternion(q);
        return {eye: apex, target: apex.clone().addScaledVector(axis, s.frustum_depth),
                fov: 2 * Math.atan(0.5 * c.h / c.fy) * 180 / Math.PI};
      }});
    });
    var first = fitView(targetCorners.concat(armPoints, D.view.sensors.map(function (p) { return new THREE.Vector3().fromArray(p); })),
                        D.view.fov_deg, aspect);
    var eye = first.eye, target = first.target;
    var dist = eye.distanceTo(target);
    var camera = new THREE.PerspectiveCamera(D.view.fov_deg, aspect, dist / 2000, dist * 200);
    camera.up.set(0, 0, 1);
    camera.position.copy(eye);
    scene.add(camera);
    scene.add(new THREE.AmbientLight(0xffffff, 0.5));
    var head = new THREE.DirectionalLight(0xffffff, 0.6);
    head.position.set(0.3, 0.6, 1);
    camera.add(head);
    var controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.target.copy(target);
    controls.screenSpacePanning = true;
    controls.update();
    function render() { renderer.render(scene, camera); }
    controls.addEventListener('change', render);

    var layers = [];
    function layer(name, object, visible) {
      object.visible = visible;
      scene.add(object);
      layers.push({name: name, object: object});
      return object;
    }

    // Meshes: targets and occluders, flat shaded; pushed back in depth so the voxel points on the
    // target surface stay on top.
    var targets = new THREE.Group(), occluders = new THREE.Group();
    D.meshes.forEach(function (m) {
      var g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(bytes(m.positions)), 3));
      g.setIndex(new THREE.BufferAttribute(new Uint32Array(bytes(m.indices)), 1));
      g.computeVertexNormals();
      var mat = new THREE.MeshPhongMaterial({color: m.target ? 0x9aa0ad : css(C.occluder), flatShading: true,
                                             shininess: 10, side: THREE.DoubleSide, polygonOffset: true,
                                             polygonOffsetFactor: 1, polygonOffsetUnits: 1});
      var mesh = new THREE.Mesh(g, mat);
      mesh.name = m.name;
      (m.target ? targets : occluders).add(mesh);
    });
    layer('occluders', occluders, true);
    layer('targets (mesh)', targets, true);

    // Reference voxels as points, by how many sensors of the layout see each (the result's
    // sensors at first; the what-if layout's as the reader changes it).
    var V = D.voxels, count = V.count;
    var idx = V.index_type === 'u16' ? new Uint16Array(bytes(V.index)) : new Int32Array(bytes(V.index));
    var F = V.cell_size;
    var voxelCentres = new Float32Array(3 * count);
    for (var i = 0; i < count; ++i) {
      for (var a = 0; a < 3; ++a) voxelCentres[3 * i + a] = (V.origin[a] + idx[3 * i + a] + 0.5) * F;
    }
    // Round point sprites, drawn on a canvas here (nothing is loaded).
    var disc = document.createElement('canvas');
    disc.width = disc.height = 64;
    var ctx = disc.getContext('2d');
    ctx.beginPath(); ctx.arc(32, 32, 29, 0, 2 * Math.PI); ctx.fillStyle = '#fff'; ctx.fill();
    ctx.lineWidth = 5; ctx.strokeStyle = '#333'; ctx.stroke();
    var discTexture = new THREE.CanvasTexture(disc);
    function points(pos, colors, size, attenuate, round, pull, opacity) {
      var g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
      g.setAttribute('color', new THREE.BufferAttribute(colors, 3));
      var options = {size: size, sizeAttenuation: attenuate, vertexColors: THREE.VertexColors};
      if (round) { options.map = discTexture; options.alphaTest = 0.1; }
      if (opacity) { options.transparent = true; options.opacity = opacity; options.depthWrite = false; }
      var material = new THREE.PointsMaterial(options);
      if (pull) {
        // A voxel centre lies up to 0.87 cell behind the surface it stands for, where the target
        // mesh would hide it: drawn `pull` metres nearer the eye, the front voxels show and the
        // back ones stay hidden.
        material.onBeforeCompile = function (shader) {
          shader.vertexShader = shader.vertexShader.replace('#include <project_vertex>',
            'vec4 mvPosition = modelViewMatrix * vec4( transformed, 1.0 );\n' +
            'mvPosition.xyz -= normalize( mvPosition.xyz ) * ' + pull.toExponential(6) + ';\n' +
            'gl_Position = projectionMatrix * mvPosition;');
        };
      }
      return new THREE.Points(g, material);
    }
    // three.js r111 draws attenuated points `size` x (half the canvas height) / depth pixels wide,
    // tan(fov/2) times a world length: scaled so that a point spans about one and a half cells.
    var voxelSize = 1.5 * F / Math.tan(D.view.fov_deg * Math.PI / 360);
    var observedPoints = layer('observed voxels',
      points(new Float32Array(3 * count), new Float32Array(3 * count), voxelSize, true, false, F), true);
    var unobservedPoints = layer('unobserved voxels',
      points(new Float32Array(3 * count), new Float32Array(3 * count), voxelSize, true, false, F), true);
    // Fills both clouds from per-voxel counts (observed: the first `o` points, unobserved: `u`).
    function colourVoxels(seen) {
      var P = observedPoints.geometry.attributes.position, Q = observedPoints.geometry.attributes.color;
      var PU = unobservedPoints.geometry.attributes.position, QU = unobservedPoints.geometry.attributes.color;
      var o = 0, u = 0;
      for (var i = 0; i < count; ++i) {
        var s = seen[i], col = s > 0 ? C.observed[Math.min(s, 3) - 1] : C.unobserved;
        var pos = s > 0 ? P.array : PU.array, colour = s > 0 ? Q.array : QU.array, k = 3 * (s > 0 ? o++ : u++);
        pos[k] = voxelCentres[3 * i]; pos[k + 1] = voxelCentres[3 * i + 1]; pos[k + 2] = voxelCentres[3 * i + 2];
        colour[k] = col[0] / 255; colour[k + 1] = col[1] / 255; colour[k + 2] = col[2] / 255;
      }
      [P, Q, PU, QU].forEach(function (attribute) { attribute.needsUpdate = true; });
      observedPoints.geometry.setDrawRange(0, o);
      unobservedPoints.geometry.setDrawRange(0, u);
      observedPoints.geometry.computeBoundingSphere();
      unobservedPoints.geometry.computeBoundingSphere();
    }
    colourVoxels(WI ? WI.seen : new Uint8Array(bytes(V.seen)));

    // Candidates: small faded points coloured by their own coverage, so that hundreds of them do
    // not hide the targets.
    var cpos = new Float32Array(3 * D.candidates.length), ccol = new Float32Array(3 * D.candidates.length);
    D.candidates.forEach(function (c, i) {
      var rgb = candidateColor(c);
      cpos[3 * i] = c.p[0]; cpos[3 * i + 1] = c.p[1]; cpos[3 * i + 2] = c.p[2];
      ccol[3 * i] = rgb[0] / 255; ccol[3 * i + 1] = rgb[1] / 255; ccol[3 * i + 2] = rgb[2] / 255;
    });
    var candidatePoints = layer('candidates', points(cpos, ccol, 5, false, true, 0, 0.45), true);

    // The lowest point of the scene (a drop line's end when nothing lies below a sensor).
    var sceneBox = new THREE.Box3();
    [targets, occluders].forEach(function (g) { sceneBox.expandByObject(g); });
    var floorZ = sceneBox.isEmpty() ? new THREE.Box3().setFromPoints(targetCorners).min.z : sceneBox.min.z;
    var dropEnds = {}, down = new THREE.Raycaster();
    // Where a line straight down from candidate c meets the first surface (cached).
    function dropEnd(c) {
      if (dropEnds[c] !== undefined) return dropEnds[c];
      var p = D.candidates[c].p;
      down.set(new THREE.Vector3(p[0], p[1], p[2]), new THREE.Vector3(0, 0, -1));
      var hits = down.intersectObjects([targets, occluders], true);
      dropEnds[c] = hits.length ? hits[0].point.z : Math.min(floorZ, p[2]);
      return dropEnds[c];
    }

    // The layout's sensors: markers (drawn over everything, so that none is hidden), a dashed
    // line straight down to the surface below (the height cue) and frusta that end at the
    // targets' far side (candidates' depth, never beyond `far`; body x forward, image u right = -y,
    // v down = -z). Translucent, the more so the more sensors, so that they do not bury the target.
    var sensors = layer('chosen sensors', new THREE.Group(), true);
    var drops = layer('height lines', new THREE.Group(), true);
    var frustaLayer = layer('frusta', new THREE.Group(), true);
    var markerSize = Math.max(dist * 0.01, 1e-4);
    var markerGeometry = new THREE.SphereBufferGeometry(markerSize, 12, 8);
    var markerMaterial = new THREE.MeshBasicMaterial({color: css(C.frustum), depthTest: false, transparent: true});
    var rimMaterial = new THREE.MeshBasicMaterial({color: 0x28303c, depthTest: false, transparent: true, side: THREE.BackSide});
    var dropMaterial = new THREE.LineDashedMaterial({color: 0x28303c, dashSize: markerSize * 1.5, gapSize: markerSize,
                                                    transparent: true, opacity: 0.8});
    function clear(group) {
      while (group.children.length) {
        var child = group.children.pop();
        if (child.geometry && child.geometry !== markerGeometry) child.geometry.dispose();
      }
    }
    function drawLayout(indices) {
      clear(sensors); clear(drops); clear(frustaLayer);
      var frusta = [], ends = [];
      indices.forEach(function (i) {
        var c = D.candidates[i];
        var q = new THREE.Quaternion(c.q[1], c.q[2], c.q[3], c.q[0]);
        var apex = new THREE.Vector3().fromArray(c.p);
        var rim = new THREE.Mesh(markerGeometry, rimMaterial);
        rim.scale.setScalar(1.35);
        rim.position.copy(apex);
        rim.renderOrder = 10;
        var marker = new THREE.Mesh(markerGeometry, markerMaterial);
        marker.position.copy(apex);
        marker.renderOrder = 11;
        sensors.add(rim, marker);
        var foot = dropEnd(i);
        if (apex.z - foot > 1e-6) ends.push(apex, new THREE.Vector3(apex.x, apex.y, foot));
        var corners = [[0, 0], [c.w, 0], [c.w, c.h], [0, c.h]].map(function (uv) {
          return new THREE.Vector3(1, -(uv[0] - c.cx) / c.fx, -(uv[1] - c.cy) / c.fy)
            .multiplyScalar(c.depth).applyQuaternion(q).add(apex);
        });
        for (var k = 0; k < 4; ++k) frusta.push(apex, corners[k], corners[k], corners[(k + 1) % 4]);
      });
      if (ends.length) {
        var dl = new THREE.LineSegments(new THREE.BufferGeometry().setFromPoints(ends), dropMaterial);
        dl.computeLineDistances();
        drops.add(dl);
      }
      var opacity = Math.max(0.25, Math.min(0.8, 2 / Math.max(1, indices.length)));
      frustaLayer.add(new THREE.LineSegments(new THREE.BufferGeometry().setFromPoints(frusta),
        new THREE.LineBasicMaterial({color: css(C.frustum), transparent: true, opacity: opacity, depthWrite: false})));
    }
    drawLayout(WI ? WI.layout : D.chosen.map(function (s) { return s.index; }));
    // The overlap graph of the result's sensors (installation constraints): a line per edge,
    // translucent; shown at first only for a few sensors, where its lines do not cover the part.
    if (D.overlap && D.overlap.length) {
      var ends = [];
      D.overlap.forEach(function (e) {
        ends.push(new THREE.Vector3().fromArray(D.candidates[e.a].p),
                  new THREE.Vector3().fromArray(D.candidates[e.b].p));
      });
      var og = new THREE.BufferGeometry().setFromPoints(ends);
      layer('overlap graph', new THREE.LineSegments(og, new THREE.LineBasicMaterial({color: 0xc2185b, transparent: true,
                                                                                   opacity: 0.55, depthWrite: false})),
            D.chosen.length <= 4);
    }

    // Keep-out boxes (mounting rules): translucent, with their edges, each in its own pose.
    if (D.keep_out && D.keep_out.length) {
      var boxes = new THREE.Group();
      var fill = new THREE.MeshBasicMaterial({color: KEEP_OUT, transparent: true, opacity: 0.15,
                                              depthWrite: false, side: THREE.DoubleSide});
      var edge = new THREE.LineBasicMaterial({color: KEEP_OUT});
      D.keep_out.forEach(function (b) {
        var g = new THREE.BoxBufferGeometry(b.size[0], b.size[1], b.size[2]);
        var box = new THREE.Group();
        box.add(new THREE.Mesh(g, fill));
        box.add(new THREE.LineSegments(new THREE.EdgesGeometry(g), edge));
        box.position.fromArray(b.center);
        box.quaternion.set(b.quaternion[1], b.quaternion[2], b.quaternion[3], b.quaternion[0]);
        box.name = b.name;
        boxes.add(box);
      });
      layer('keep-out boxes', boxes, true);
    }

    // A camera on an arm: the arm ghosted at each view of the tour, the camera's path.
    if (D.arm && D.arm.links.length && D.arm.stops.length) {
      var ghosts = new THREE.Group();
      var ghostMaterial = new THREE.MeshPhongMaterial({color: ARM, transparent: true, opacity: 0.14,
                                                       depthWrite: false, side: THREE.DoubleSide});
      var linkGeometry = D.arm.links.map(function (m) {
        var g = new THREE.BufferGeometry();
        g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(bytes(m.positions)), 3));
        g.setIndex(new THREE.BufferAttribute(new Uint32Array(bytes(m.indices)), 1));
        g.computeVertexNormals();
        return g;
      });
      D.arm.stops.forEach(function (stop) {
        stop.links.forEach(function (p, l) {
          var mesh = new THREE.Mesh(linkGeometry[l], ghostMaterial);
          mesh.position.set(p[0], p[1], p[2]);
          mesh.quaternion.set(p[4], p[5], p[6], p[3]);
          mesh.name = stop.name + ' ' + D.arm.links[l].name;
          ghosts.add(mesh);
        });
      });
      layer('arm at the views (ghosted)', ghosts, true);
      var path = new THREE.BufferGeometry();
      var along = new Float32Array(3 * D.arm.stops.length);
      D.arm.stops.forEach(function (stop, k) { for (var a = 0; a < 3; ++a) along[3 * k + a] = stop.camera[a]; });
      path.setAttribute('position', new THREE.BufferAttribute(along, 3));
      layer('camera path (tour order)', new THREE.Line(path, new THREE.LineBasicMaterial({color: ARM})), true);
    }

    // Layer toggles and legend.
    var panel = document.getElementById('layers');
    layers.forEach(function (l) {
      var label = document.createElement('label'), box = document.createElement('input');
      box.type = 'checkbox';
      box.checked = l.object.visible;
      box.addEventListener('change', function () { l.object.visible = box.checked; render(); });
      l.box = box;
      label.appendChild(box);
      label.appendChild(document.createTextNode(' ' + l.name));
      panel.appendChild(label);
    });
    function setLayer(name, visible) {
      layers.forEach(function (l) {
        if (l.name !== name) return;
        l.object.visible = visible;
        l.box.checked = visible;
      });
    }
    // Views to pick (the page opens on the first, or on #view=KEY of its address: sensors,
    // targets, below, sensor1, ...); picking one again resets the orbit. A view may hide layers
    // (from below: the occluders) until another view is picked.
    var pickView = document.createElement('select');
    pickView.id = 'view-pick';
    views.forEach(function (v, k) {
      var option = document.createElement('option');
      option.value = String(k);
      option.textContent = v.name;
      pickView.appendChild(option);
    });
    // The panels stand over the canvas's sides (layers and legend at the left, the what-if at the
    // right): a fitted view frames its points in the band between them, so that no chosen camera
    // is drawn under a panel (issue 46: at 1,000-1,400 pixels wide the layers panel and the what-if
    // covered two of the example's three). Null where that band is under a quarter of the canvas.
    function freeBand() {
      var box = view.getBoundingClientRect(), width = view.clientWidth, height = view.clientHeight;
      var left = 0, right = width, margin = 8;
      function edges(id, side) {
        var e = document.getElementById(id);
        if (!e || !e.offsetWidth || !e.offsetHeight) return;
        var r = e.getBoundingClientRect();
        if (r.bottom <= box.top || r.top >= box.bottom) return;
        if (side < 0) left = Math.max(left, r.right - box.left + margin);
        else right = Math.min(right, r.left - box.left - margin);
      }
      edges('layers', -1);
      edges('legend', -1);
      edges('whatif', 1);
      if (right - left < 0.25 * width || height <= 0) return null;
      return {left: left, right: right, width: right - left, height: height, canvasWidth: width};
    }
    // The picture's centre (where the view's target is drawn) moved to the band's centre: a view
    // offset shifts the whole image, so a fit in the band's aspect stays inside the band.
    function offsetTo(band) {
      if (band) {
        camera.setViewOffset(band.canvasWidth, band.height, band.canvasWidth / 2 - (band.left + band.right) / 2, 0,
                             band.canvasWidth, band.height);
      } else {
        camera.clearViewOffset();
      }
      camera.updateProjectionMatrix();
    }
    var hidden = [];
    function show(k) {
      hidden.forEach(function (name) { setLayer(name, true); });
      hidden = (views[k].hide || []).slice();
      hidden.forEach(function (name) { setLayer(name, false); });
      moved = false;
      var band = views[k].fitted ? freeBand() : null;
      var v = views[k].make(band ? band.width / band.height : camera.aspect);
      camera.fov = v.fov;
      offsetTo(band);
      camera.position.copy(v.eye);
      controls.target.copy(v.target);
      controls.update();
      render();
    }
    pickView.addEventListener('change', function () { show(Number(pickView.value)); });
    var again = document.createElement('button');
    again.textContent = 'reset view';
    again.addEventListener('click', function () { show(Number(pickView.value)); });
    var row = document.createElement('div');
    row.className = 'views';
    row.appendChild(document.createTextNode('view '));
    row.appendChild(pickView);
    row.appendChild(again);
    panel.appendChild(row);
    var wanted = /(?:^#|&)view=([A-Za-z0-9]+)/.exec(window.location.hash);
    views.forEach(function (v, k) { if (wanted && wanted[1] === v.key) pickView.value = String(k); });
    // A canvas too narrow for a picture between the panels starts with the legend folded (its
    // rows are the widest panel at the left; a click on "legend" unfolds it).
    var legendBox = document.querySelector('#legend details');
    if (!freeBand() && legendBox && legendBox.open) legendBox.open = false;
    show(Number(pickView.value));

    // The what-if layout drawn live: voxel colours, markers, height lines and frusta.
    if (WI) {
      WI.listeners.push(function () {
        colourVoxels(WI.seen);
        drawLayout(WI.layout);
        render();
      });
    }

    // Click a candidate (the nearest marker within 10 pixels of the click, not a drag): its name
    // and numbers, its row in the table, and it joins or leaves the what-if layout.
    var pick = document.getElementById('pick');
    function screenOf(p) {
      var rect = renderer.domElement.getBoundingClientRect();
      var v = new THREE.Vector3(p[0], p[1], p[2]).project(camera);
      return {x: rect.left + (v.x + 1) / 2 * rect.width, y: rect.top + (1 - v.y) / 2 * rect.height,
              inside: v.z > -1 && v.z < 1 && Math.abs(v.x) <= 1 && Math.abs(v.y) <= 1};
    }
    var pressed = null;
    renderer.domElement.addEventListener('pointerdown', function (ev) { pressed = {x: ev.clientX, y: ev.clientY}; });
    renderer.domElement.addEventListener('click', function (ev) {
      if (pressed && Math.hypot(ev.clientX - pressed.x, ev.clientY - pressed.y) > 4) return;  // an orbit
      var best = -1, bestDistance = 10;
      if (candidatePoints.visible) {
        D.candidates.forEach(function (c, i) {
          var s = screenOf(c.p);
          if (!s.inside) return;
          var d = Math.hypot(s.x - ev.clientX, s.y - ev.clientY);
          if (d < bestDistance) { best = i; bestDistance = d; }
        });
      }
      var prev = document.querySelectorAll('#candidates-table tr.hl');
      Array.prototype.forEach.call(prev, function (tr) { tr.classList.remove('hl'); });
      if (best < 0) { pick.style.display = 'none'; return; }
      var i = best, c = D.candidates[i];
      if (WI) WI.toggle(i);
      pick.style.display = 'block';
      pick.innerHTML = '<b>' + esc(c.name) + '</b> (' + esc(c.type) + ')<br>position ' +
        c.p.map(function (v) { return v.toFixed(3); }).join(', ') + ' m<br>coverage alone ' + pct(c.coverage) +
        (chosenOrder[i] ? '<br>chosen #' + chosenOrder[i] : '') +
        (WI ? '<br>' + (WI.inLayout[i] ? 'added to' : 'removed from') + ' the what-if layout' : '');
      var row = document.querySelector('#candidates-table tr[data-id="' + i + '"]');
      if (row) { row.classList.add('hl'); }
    });
    // For scripts driving the page: where candidate i and the layout's sensors are on screen.
    window.vantagePage.screenOf = function (i) { return screenOf(D.candidates[i].p); };
    window.vantagePage.view = function () { return views[Number(pickView.value)].key; };

    // Until the reader moves the view, a resize fits the picked view again (the page may first
    // lay out narrower than its window); after that it keeps their view.
    var moved = false;
    controls.addEventListener('start', function () { moved = true; });
    window.addEventListener('resize', function () {
      camera.aspect = view.clientWidth / view.clientHeight;
      if (!moved) show(Number(pickView.value));
      else offsetTo(camera.view && camera.view.enabled ? freeBand() : null);
      renderer.setSize(view.clientWidth, view.clientHeight);
      render();
    });
    render();
  }

  // The legend stays a few short rows whatever the number of sensors (issue 46: eight sensors'
  // 28 overlap counts ran across the view and covered the part), and folds away.
  guarded('legend', function () {
    var lg = document.getElementById('legend');
    function sensorsWord(k) {
      return (WI ? 'sensor' + (k ? 's' : '') + ' of the layout' : 'chosen sensor' + (k ? 's' : ''));
    }
    var rows = [['sw', css(C.unobserved), 'target voxel not observed']];
    C.observed.forEach(function (c, k) {
      rows.push(['sw', css(c), 'observed by ' + (k + 1) + (k === C.observed.length - 1 ? '+' : '') + ' ' + sensorsWord(k)]);
    });
    rows.push(['sw', css(C.frustum), (WI ? 'sensors of the layout' : 'chosen sensors') + ', frusta to the targets']);
    rows.push(['line', '#28303c', 'height: dashed line down to the surface below']);
    if (D.overlap && D.overlap.length) {
      var cells = D.overlap.map(function (e) { return e.cells; });
      rows.push(['sw', '#c2185b', D.overlap.length <= 3
        ? 'overlap graph: chosen sensors sharing cells (' + cells.join(', ') + ' cells)'
        : 'overlap graph: ' + D.overlap.length + ' pairs of chosen sensors share cells (' +
          Math.min.apply(null, cells) + '–' + Math.max.apply(null, cells) + ' cells a pair)']);
    }
    if (D.arm && D.arm.stops.length) {
      rows.push(['sw', ARM, 'robot ' + D.arm.robot + ' at each view (ghosted), the camera path in tour order']);
    }
    if (D.keep_out && D.keep_out.length) {
      var names = D.keep_out.map(function (b) { return b.name; });
      rows.push(['sw', KEEP_OUT, 'keep-out box' + (names.length > 1 ? 'es' : '') + ' (no sensor inside): ' +
        (names.length <= 4 ? names.join(', ') : names.slice(0, 3).join(', ') + ' and ' + (names.length - 3) + ' more')]);
    }
    var stops = [0, 0.25, 0.5, 0.75, 1].map(function (t) { return css(ramp(t).map(Math.round)); }).join(',');
    lg.innerHTML = '<details open><summary>legend</summary>' + rows.map(function (r) {
      return '<div class="row"><span class="' + r[0] + '" style="' + (r[0] === 'line' ? 'color:' : 'background:') + r[1] +
        '"></span>' + esc(r[2]) + '</div>';
    }).join('') + '<div class="row">candidates' + (WI ? ' (click: add / remove)' : '') + ': ' + pct(covMin) +
      ' <span class="ramp" style="background:linear-gradient(to right,' + stops + ')"></span> ' + pct(covMax) + '</div></details>';
  });

  if (!window.THREE || !window.THREE.OrbitControls) {
    note(D.three_note || 'The 3D view is not available: three.js was not embedded in this page.');
  } else {
    guarded('3D view', function () {
      try { build3D(); } catch (e) { note('The 3D view could not be built: ' + (e && e.message ? e.message : e)); throw e; }
    });
  }

  var status = document.getElementById('vantage-status');
  if (status.className !== 'bad') {
    status.textContent = problems.length ? 'error: ' + problems.join('; ') : 'ok';
    status.className = problems.length ? 'bad' : '';
  }
})();
