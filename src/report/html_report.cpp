// report.html (issue #7; docs/outputs.md): one self-contained page. three.js r111 from Debian's
// libjs-three is read at run time and inlined, the data is embedded as JSON (bulk arrays as
// base64 typed arrays), the chart and the sortable tables are drawn by the page's own small
// script. Nothing is fetched: the page opens from disk without network access.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>
#include <string_view>
#include <unordered_map>

#include "util/markup.hpp"
#include "vantage/error.hpp"
#include "vantage/visualize.hpp"

namespace vantage {
namespace {

using nlohmann::ordered_json;

// ---------------------------------------------------------------------------------------------
// Page template. @TITLE@, @SUBTITLE@, @THREE@ and @DATA@ are replaced once each.

constexpr const char* kPageHead = R"HTML(<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<meta name="viewport" content="width=device-width, initial-scale=1">
<title>@TITLE@</title>
<style>
  :root { --fg: #1d232b; --muted: #5d6875; --line: #d5dbe2; --bg: #ffffff; --panel: #f4f6f9; }
  * { box-sizing: border-box; }
  body { margin: 0; font: 14px/1.45 system-ui, -apple-system, "Segoe UI", Roboto, sans-serif;
         color: var(--fg); background: var(--bg); }
  header { padding: 8px 16px; border-bottom: 1px solid var(--line); display: flex; gap: 16px;
           align-items: baseline; flex-wrap: wrap; }
  header h1 { font-size: 17px; margin: 0; }
  header .sub { color: var(--muted); font-size: 13px; }
  main { padding: 0 16px 24px; }
  h2 { font-size: 15px; margin: 22px 0 8px; }
  #view { position: relative; height: 480px; margin: 0 -16px; background: #eef1f5; overflow: hidden; }
  #view canvas { display: block; }
  .panel { position: absolute; background: rgba(255,255,255,0.88); border: 1px solid var(--line);
           border-radius: 6px; padding: 6px 9px; font-size: 12px; }
  #layers { top: 8px; left: 8px; }
  #layers label { display: block; white-space: nowrap; cursor: pointer; }
  #layers button { margin-top: 4px; font-size: 12px; }
  #legend { bottom: 8px; left: 8px; }
  #legend .row { display: flex; align-items: center; gap: 6px; white-space: nowrap; }
  .sw { display: inline-block; width: 12px; height: 12px; border-radius: 2px; border: 1px solid #0003; }
  .ramp { display: inline-block; width: 90px; height: 10px; border: 1px solid #0003; }
  #pick { top: 8px; right: 8px; max-width: 320px; display: none; }
  .note { background: #fff6d6; border: 1px solid #e8d48a; border-radius: 6px; padding: 8px 12px; margin: 10px 0; }
  #view .note { position: absolute; top: 40%; left: 50%; transform: translate(-50%, -50%); max-width: 560px; }
  .notes li { color: var(--muted); }
  #chart-box svg { max-width: 100%; height: auto; font-size: 12px; }
  table { border-collapse: collapse; font-size: 12.5px; font-variant-numeric: tabular-nums; }
  th, td { padding: 3px 8px; border-bottom: 1px solid var(--line); text-align: left; white-space: nowrap; }
  td.num, th.num { text-align: right; }
  th { position: sticky; top: 0; background: var(--panel); cursor: pointer; user-select: none; }
  th[aria-sort="ascending"]::after { content: " \25B2"; font-size: 10px; }
  th[aria-sort="descending"]::after { content: " \25BC"; font-size: 10px; }
  tr.chosen td { background: #fff3c4; }
  tr.hl td { background: #d9ecff; }
  .scroll { max-height: 420px; overflow: auto; border: 1px solid var(--line); display: inline-block; max-width: 100%; }
  footer { padding: 8px 16px; color: var(--muted); font-size: 12px; border-top: 1px solid var(--line); }
  #vantage-status.bad { color: #b3261e; font-weight: bold; }
</style>
</head>
<body>
<header><h1>@TITLE@</h1><span class="sub">@SUBTITLE@</span></header>
<main>
<div id="view">
  <div id="layers" class="panel"></div>
  <div id="legend" class="panel"></div>
  <div id="pick" class="panel"></div>
</div>
<ul id="notes" class="notes"></ul>
<h2>Coverage versus number of sensors</h2>
<div id="chart-box"></div>
<h2 id="chosen-title">Chosen sensors</h2>
<div class="scroll"><table id="chosen-table"></table></div>
<h2>Results</h2>
<div class="scroll"><table id="results-table"></table></div>
<h2 id="robustness-title">Robustness</h2>
<p id="robustness-text"></p>
<div class="scroll"><table id="robustness-table"></table></div>
<h2 id="candidates-title">Candidates</h2>
<div class="scroll"><table id="candidates-table"></table></div>
</main>
<footer>vantage report &middot; page status: <span id="vantage-status">loading</span></footer>
<script>
window.onerror = function (message) {
  var s = document.getElementById('vantage-status');
  s.textContent = 'error: ' + message;
  s.className = 'bad';
};
</script>
)HTML";

constexpr const char* kPageScript = R"JS(
(function () {
  'use strict';
  var D = JSON.parse(document.getElementById('vantage-data').textContent);
  var problems = [];
  var C = D.colors;

  function esc(s) {
    return String(s).replace(/[&<>"']/g, function (c) {
      return {'&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;'}[c];
    });
  }
  function pct(x) { return x === null || x === undefined ? '' : (100 * x).toFixed(2) + ' %'; }
  function fix(x, d) { return x === null || x === undefined ? '' : Number(x).toFixed(d); }
  function css(rgb) { return 'rgb(' + rgb[0] + ',' + rgb[1] + ',' + rgb[2] + ')'; }
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
     }) : []), D.results);

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
        text += ' With every field of view ' + rb.fov_tolerance_deg + '° narrower: ' + pct(rb.fov_shrunk_coverage) + '.';
      document.getElementById('robustness-text').textContent = text;
      var rows = rb.sensor_failures.map(function (f) {
        return {what: 'fails', sensor: f.sensor, other: '', coverage: f.coverage, change: f.coverage - base.coverage};
      }).concat(rb.alternatives.map(function (a) {
        return {what: 'replaced by', sensor: a.replaced, other: a.replacement, coverage: a.coverage, change: a.coverage - base.coverage};
      }));
      makeTable(document.getElementById('robustness-table'), [
        {label: 'sensor', value: function (r) { return r.sensor; }},
        {label: 'event', value: function (r) { return r.what; }},
        {label: 'replacement', value: function (r) { return r.other; }},
        {label: 'coverage', num: true, value: function (r) { return r.coverage; }, show: pct},
        {label: 'change [points]', num: true, value: function (r) { return 100 * r.change; }, show: function (v) { return fix(v, 2); }}
      ], rows);
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

  // ------------------------------------------------------------------ chart
  guarded('chart', function () {
    var SVG = 'http://www.w3.org/2000/svg';
    var W = 760, H = 340, L = 56, R = 200, T = 16, B = 44;
    var series = {}, order = [];
    D.results.forEach(function (r) {
      if (!series[r.method]) { series[r.method] = []; order.push(r.method); }
      series[r.method].push(r);
    });
    var maxN = 1, maxY = 0;
    D.results.forEach(function (r) {
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
    var palette = ['#1f77b4', '#ff7f0e', '#2ca02c', '#d62728', '#9467bd', '#8c564b', '#e377c2', '#17becf'];
    order.forEach(function (method, m) {
      var color = palette[m % palette.length];
      var pts = series[method].slice().sort(function (a, b) { return a.n - b.n; });
      var g = el('g', {'class': 'series', 'data-method': method}, svg);
      if (pts.length > 1)
        el('polyline', {points: pts.map(function (r) { return X(r.n) + ',' + Y(r.coverage); }).join(' '),
                        fill: 'none', stroke: color, 'stroke-width': 2}, g);
      pts.forEach(function (r) {
        var c = el('circle', {cx: X(r.n), cy: Y(r.coverage), r: 4, fill: color}, g);
        el('title', {}, c, method + ', N = ' + r.n + ': ' + pct(r.coverage));
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
      el('line', {x1: W - R + 14, x2: W - R + 38, y1: cy, y2: cy, stroke: '#5d6875', 'stroke-width': 1.5,
                  'stroke-dasharray': '2 3'}, svg);
      el('text', {x: W - R + 44, y: cy + 4, fill: '#1d232b'}, svg, 'primary, in order chosen');
    }
    if (!D.results.length) el('text', {x: (L + W - R) / 2, y: (T + H - B) / 2, 'text-anchor': 'middle'}, svg, 'no results');
    document.getElementById('chart-box').appendChild(svg);
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
    var eye = new THREE.Vector3().fromArray(D.view.eye), target = new THREE.Vector3().fromArray(D.view.look_at);
    var dist = eye.distanceTo(target);
    var camera = new THREE.PerspectiveCamera(D.view.fov_deg, view.clientWidth / view.clientHeight,
                                             dist / 2000, dist * 200);
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

    // Reference voxels as points, by how many chosen sensors see each.
    var V = D.voxels, count = V.count;
    var idx = V.index_type === 'u16' ? new Uint16Array(bytes(V.index)) : new Int32Array(bytes(V.index));
    var seen = new Uint8Array(bytes(V.seen));
    var nObserved = 0;
    for (var i = 0; i < count; ++i) if (seen[i] > 0) ++nObserved;
    var posO = new Float32Array(3 * nObserved), colO = new Float32Array(3 * nObserved);
    var posU = new Float32Array(3 * (count - nObserved)), colU = new Float32Array(3 * (count - nObserved));
    var o = 0, u = 0, F = V.cell_size;
    for (i = 0; i < count; ++i) {
      var x = (V.origin[0] + idx[3 * i] + 0.5) * F, y = (V.origin[1] + idx[3 * i + 1] + 0.5) * F,
          z = (V.origin[2] + idx[3 * i + 2] + 0.5) * F;
      var col = seen[i] > 0 ? C.observed[Math.min(seen[i], 3) - 1] : C.unobserved;
      var P = seen[i] > 0 ? posO : posU, Q = seen[i] > 0 ? colO : colU, k = 3 * (seen[i] > 0 ? o++ : u++);
      P[k] = x; P[k + 1] = y; P[k + 2] = z;
      Q[k] = col[0] / 255; Q[k + 1] = col[1] / 255; Q[k + 2] = col[2] / 255;
    }
    // Round point sprites, drawn on a canvas here (nothing is loaded).
    var disc = document.createElement('canvas');
    disc.width = disc.height = 64;
    var ctx = disc.getContext('2d');
    ctx.beginPath(); ctx.arc(32, 32, 29, 0, 2 * Math.PI); ctx.fillStyle = '#fff'; ctx.fill();
    ctx.lineWidth = 5; ctx.strokeStyle = '#333'; ctx.stroke();
    var discTexture = new THREE.CanvasTexture(disc);
    function points(pos, colors, size, attenuate, round, pull) {
      var g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
      g.setAttribute('color', new THREE.BufferAttribute(colors, 3));
      var options = {size: size, sizeAttenuation: attenuate, vertexColors: THREE.VertexColors};
      if (round) { options.map = discTexture; options.alphaTest = 0.5; }
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
    layer('observed voxels', points(posO, colO, voxelSize, true, false, F), true);
    layer('unobserved voxels', points(posU, colU, voxelSize, true, false, F), true);

    // Candidates: points coloured by their own coverage.
    var cpos = new Float32Array(3 * D.candidates.length), ccol = new Float32Array(3 * D.candidates.length);
    D.candidates.forEach(function (c, i) {
      var rgb = candidateColor(c);
      cpos[3 * i] = c.p[0]; cpos[3 * i + 1] = c.p[1]; cpos[3 * i + 2] = c.p[2];
      ccol[3 * i] = rgb[0] / 255; ccol[3 * i + 1] = rgb[1] / 255; ccol[3 * i + 2] = rgb[2] / 255;
    });
    var candidatePoints = layer('candidates', points(cpos, ccol, 9, false, true), true);

    // Chosen sensors: markers and frusta cut at `far` (body x forward, image u right = -y, v down = -z).
    var sensors = new THREE.Group(), frusta = [];
    var markerSize = Math.max(dist * 0.008, 1e-4);
    var markerGeometry = new THREE.SphereBufferGeometry(markerSize, 12, 8);
    var markerMaterial = new THREE.MeshBasicMaterial({color: css(C.frustum)});
    D.chosen.forEach(function (s) {
      var c = D.candidates[s.index];
      var q = new THREE.Quaternion(c.q[1], c.q[2], c.q[3], c.q[0]);
      var apex = new THREE.Vector3().fromArray(c.p);
      var marker = new THREE.Mesh(markerGeometry, markerMaterial);
      marker.position.copy(apex);
      sensors.add(marker);
      var corners = [[0, 0], [c.w, 0], [c.w, c.h], [0, c.h]].map(function (uv) {
        return new THREE.Vector3(1, -(uv[0] - c.cx) / c.fx, -(uv[1] - c.cy) / c.fy)
          .multiplyScalar(c.far).applyQuaternion(q).add(apex);
      });
      for (var k = 0; k < 4; ++k) {
        frusta.push(apex, corners[k], corners[k], corners[(k + 1) % 4]);
      }
    });
    layer('chosen sensors', sensors, true);
    var fg = new THREE.BufferGeometry().setFromPoints(frusta);
    layer('frusta', new THREE.LineSegments(fg, new THREE.LineBasicMaterial({color: css(C.frustum)})), true);

    // Layer toggles and legend.
    var panel = document.getElementById('layers');
    layers.forEach(function (l) {
      var label = document.createElement('label'), box = document.createElement('input');
      box.type = 'checkbox';
      box.checked = l.object.visible;
      box.addEventListener('change', function () { l.object.visible = box.checked; render(); });
      label.appendChild(box);
      label.appendChild(document.createTextNode(' ' + l.name));
      panel.appendChild(label);
    });
    var reset = document.createElement('button');
    reset.textContent = 'reset view';
    reset.addEventListener('click', function () {
      camera.position.copy(eye); controls.target.copy(target); controls.update(); render();
    });
    panel.appendChild(reset);

    // Click a candidate: its name and numbers, and its row in the table.
    var raycaster = new THREE.Raycaster(), mouse = new THREE.Vector2(), pick = document.getElementById('pick');
    renderer.domElement.addEventListener('click', function (ev) {
      var rect = renderer.domElement.getBoundingClientRect();
      mouse.x = (ev.clientX - rect.left) / rect.width * 2 - 1;
      mouse.y = -(ev.clientY - rect.top) / rect.height * 2 + 1;
      raycaster.params.Points.threshold = dist * 0.01;
      raycaster.setFromCamera(mouse, camera);
      var hits = candidatePoints.visible ? raycaster.intersectObject(candidatePoints) : [];
      var prev = document.querySelectorAll('#candidates-table tr.hl');
      Array.prototype.forEach.call(prev, function (tr) { tr.classList.remove('hl'); });
      if (!hits.length) { pick.style.display = 'none'; return; }
      var i = hits[0].index, c = D.candidates[i];
      pick.style.display = 'block';
      pick.innerHTML = '<b>' + esc(c.name) + '</b> (' + esc(c.type) + ')<br>position ' +
        c.p.map(function (v) { return v.toFixed(3); }).join(', ') + ' m<br>coverage ' + pct(c.coverage) +
        (chosenOrder[i] ? '<br>chosen #' + chosenOrder[i] : '');
      var row = document.querySelector('#candidates-table tr[data-id="' + i + '"]');
      if (row) { row.classList.add('hl'); }
    });

    window.addEventListener('resize', function () {
      camera.aspect = view.clientWidth / view.clientHeight;
      camera.updateProjectionMatrix();
      renderer.setSize(view.clientWidth, view.clientHeight);
      render();
    });
    render();
  }

  guarded('legend', function () {
    var lg = document.getElementById('legend');
    var rows = [['sw', css(C.unobserved), 'target voxel not observed']];
    C.observed.forEach(function (c, k) {
      rows.push(['sw', css(c), 'observed by ' + (k + 1) + (k === C.observed.length - 1 ? '+' : '') + ' chosen sensor' + (k ? 's' : '')]);
    });
    rows.push(['sw', css(C.frustum), 'chosen sensors, frusta cut at far']);
    var stops = [0, 0.25, 0.5, 0.75, 1].map(function (t) { return css(ramp(t).map(Math.round)); }).join(',');
    lg.innerHTML = rows.map(function (r) {
      return '<div class="row"><span class="' + r[0] + '" style="background:' + r[1] + '"></span>' + esc(r[2]) + '</div>';
    }).join('') + '<div class="row">candidates: ' + pct(covMin) + ' <span class="ramp" style="background:linear-gradient(to right,' +
      stops + ')"></span> ' + pct(covMax) + '</div>';
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
)JS";

// ---------------------------------------------------------------------------------------------

std::vector<uint32_t> PrimaryChosen(const Report& report, int* primary_index) {
  const int primary = report.primary >= 0 ? report.primary : PrimaryResult(report.results);
  *primary_index = primary >= 0 && primary < static_cast<int>(report.results.size()) ? primary : -1;
  if (*primary_index < 0) return {};
  return report.results[static_cast<size_t>(primary)].chosen;
}

std::string Base64(const void* bytes, size_t size) {
  static constexpr std::string_view kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* in = static_cast<const uint8_t*>(bytes);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 2 < size; i += 3) {
    const uint32_t v = (uint32_t{in[i]} << 16) | (uint32_t{in[i + 1]} << 8) | in[i + 2];
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  if (i + 1 == size) {
    const uint32_t v = uint32_t{in[i]} << 16;
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += "==";
  } else if (i + 2 == size) {
    const uint32_t v = (uint32_t{in[i]} << 16) | (uint32_t{in[i + 1]} << 8);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += '=';
  }
  return out;
}

template <typename T>
std::string Base64(const std::vector<T>& values) {
  return Base64(values.data(), values.size() * sizeof(T));
}


// Inlined script text must neither close its <script> element early nor open an HTML comment
// (HTML, script data state): "</script" and "<!--" get a backslash that JavaScript ignores inside
// string and regular-expression literals, where such text can appear.
std::string ScriptSafe(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    out += text[i];
    if (text[i] != '<') continue;
    const std::string_view rest = std::string_view(text).substr(i + 1);
    const bool is_close =
        rest.size() >= 7 && rest[0] == '/' &&
        std::equal(rest.begin() + 1, rest.begin() + 7, "script",
                   [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
    if (is_close || rest.substr(0, 3) == "!--") out += '\\';
  }
  return out;
}

// JSON for a <script type="application/json"> element: '<' only occurs inside strings, where
// \u003c means the same and can never start a tag.
std::string JsonScriptSafe(const std::string& json) {
  std::string out;
  out.reserve(json.size());
  for (const char ch : json) {
    if (ch == '<') {
      out += "\\u003c";
    } else {
      out += ch;
    }
  }
  return out;
}

bool ReadFile(const std::string& path, std::string* text) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  text->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return in.good() || in.eof();
}

struct IndexHash {
  size_t operator()(const std::array<int64_t, 3>& k) const {
    uint64_t h = 1469598103934665603ull;
    for (const int64_t v : k) h = (h ^ static_cast<uint64_t>(v)) * 1099511628211ull;
    return static_cast<size_t>(h);
  }
};

// Vertex clustering: vertices in one cell of size `cell` merge into their mean; triangles that
// collapse or repeat are dropped. Keeps the silhouette of huge meshes at a bounded size.
TriangleMesh ClusterVertices(const TriangleMesh& mesh, double cell) {
  std::unordered_map<std::array<int64_t, 3>, uint32_t, IndexHash> cluster_of_cell;
  std::vector<uint32_t> cluster(mesh.vertices.size());
  std::vector<Vec3> sums;
  std::vector<int> counts;
  for (size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3& v = mesh.vertices[i];
    const std::array<int64_t, 3> key = {static_cast<int64_t>(std::floor(v.x() / cell)),
                                        static_cast<int64_t>(std::floor(v.y() / cell)),
                                        static_cast<int64_t>(std::floor(v.z() / cell))};
    const auto [it, is_new] = cluster_of_cell.try_emplace(key, static_cast<uint32_t>(sums.size()));
    if (is_new) {
      sums.emplace_back(Vec3::Zero());
      counts.push_back(0);
    }
    cluster[i] = it->second;
    sums[it->second] += v;
    ++counts[it->second];
  }
  TriangleMesh out;
  out.vertices.resize(sums.size());
  for (size_t i = 0; i < sums.size(); ++i) out.vertices[i] = sums[i] / counts[i];
  std::set<std::array<uint32_t, 3>> seen;
  for (const auto& t : mesh.triangles) {
    const std::array<uint32_t, 3> c = {cluster[t[0]], cluster[t[1]], cluster[t[2]]};
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
    std::array<uint32_t, 3> sorted = c;
    std::sort(sorted.begin(), sorted.end());
    if (!seen.insert(sorted).second) continue;
    out.triangles.push_back(c);
  }
  return out;
}

// The meshes embedded in the page: the scene's own, or simplified until they fit the budget.
std::vector<TriangleMesh> PageMeshes(const Scene& scene, size_t max_triangles, std::string* note) {
  std::vector<TriangleMesh> meshes;
  for (const SceneObject& object : scene.objects) meshes.push_back(object.mesh);
  const size_t total = scene.TriangleCount();
  if (total <= max_triangles) return meshes;
  Aabb bounds;
  for (const TriangleMesh& mesh : meshes) {
    if (!mesh.IsEmpty()) bounds.Extend(mesh.Bounds());
  }
  const double diagonal = (bounds.max - bounds.min).norm();
  double cell = diagonal / 4096.0;
  for (int round = 0; round < 40; ++round, cell *= 1.4) {
    std::vector<TriangleMesh> simplified;
    size_t count = 0;
    for (const SceneObject& object : scene.objects) {
      simplified.push_back(ClusterVertices(object.mesh, cell));
      count += simplified.back().triangles.size();
    }
    if (count <= max_triangles || round == 39) {
      *note = fmt::format(
          "The 3D view shows the meshes simplified from {} to {} triangles "
          "(vertex clustering, {:.3g} m cells); pictures and numbers use the full meshes.",
          total, count, cell);
      return simplified;
    }
  }
  return meshes;
}

ordered_json Vec3Json(const Vec3& v) { return ordered_json::array({v.x(), v.y(), v.z()}); }
ordered_json RgbJson(const Rgb& c) { return ordered_json::array({c[0], c[1], c[2]}); }

}  // namespace

std::string HtmlReport(const Report& report, const Scene& scene, const HtmlReportOptions& options) {
  VANTAGE_CHECK(report.data != nullptr);
  VANTAGE_CHECK(options.max_mesh_triangles >= 1);
  const VisibilityFile& data = *report.data;
  const size_t reference_size = data.reference.keys.size();
  const auto fraction = [&](size_t count) {
    return reference_size ? static_cast<double>(count) / static_cast<double>(reference_size) : 0.0;
  };
  int primary = -1;
  const std::vector<uint32_t> chosen = PrimaryChosen(report, &primary);

  ordered_json page;
  std::vector<std::string> notes = report.notes;

  // Candidates.
  ordered_json candidates = ordered_json::array();
  for (size_t i = 0; i < data.candidates.size(); ++i) {
    const Candidate& c = data.candidates[i];
    const Observation& o = data.observations.at(i);
    const Quat q = c.world_from_body.rotation.normalized();
    const SensorType& s = c.sensor;
    candidates.push_back(
        {{"name", c.name},
         {"type", c.type_id.empty() ? s.id : c.type_id},
         {"population", c.population},
         {"p", Vec3Json(c.world_from_body.position)},
         {"q", ordered_json::array({q.w(), q.x(), q.y(), q.z()})},
         {"w", s.width},
         {"h", s.height},
         {"fx", s.fx},
         {"fy", s.fy},
         {"cx", s.cx},
         {"cy", s.cy},
         {"near", s.near},
         {"far", s.far},
         {"observed", o.reference_indices.size()},
         {"coverage", fraction(o.reference_indices.size())},
         {"paper_coverage", fraction(o.reference_indices.size() + o.outside_keys.size())}});
  }

  // Results.
  // Copies every set: only when a quality filter makes plain coverage differ.
  const std::vector<Observation> plain =
      data.quality.active() ? WithoutQuality(data.observations) : std::vector<Observation>{};
  const CoverageEvaluator plain_evaluator(plain, reference_size);
  ordered_json results = ordered_json::array();
  for (const Selection& s : report.results) {
    ordered_json r = {{"method", s.method},
                      {"n", s.n},
                      {"sensors", s.chosen},
                      {"coverage", s.coverage},
                      {"paper_coverage", s.paper_coverage},
                      {"seconds", s.seconds}};
    if (s.upper_bound) {
      r["upper_bound"] = *s.upper_bound;
      r["optimal"] = s.proven_optimal;
    }
    if (data.quality.active() && !report.states) r["plain_coverage"] = plain_evaluator.Coverage(s.chosen, s.k);
    if (!s.state_coverage.empty()) r["state_coverage"] = s.state_coverage;
    results.push_back(std::move(r));
  }

  // Chosen sensors in the order chosen, with marginal gains, and per reference voxel how many of
  // them observe it.
  std::vector<uint8_t> seen(reference_size, 0);
  ordered_json chosen_json = ordered_json::array();
  size_t covered = 0;
  for (uint32_t index : chosen) {
    VANTAGE_CHECK(index < data.candidates.size());
    size_t gained = 0;
    for (uint32_t r : data.observations[index].reference_indices) {
      if (seen[r] == 0) ++gained;
      if (seen[r] < 255) ++seen[r];
    }
    covered += gained;
    const Vec3 rpy = RpyFromRotation(
        data.candidates[index].world_from_body.rotation.normalized().toRotationMatrix());
    chosen_json.push_back({{"index", index},
                           {"marginal_gain", fraction(gained)},
                           {"cumulative", fraction(covered)},
                           {"rpy_deg", Vec3Json(rpy * (180.0 / 3.14159265358979323846))}});
  }

  // Reference voxels as integer cell indices relative to the smallest, 16 bits when they fit.
  ordered_json voxels;
  {
    std::array<int64_t, 3> lo = {0, 0, 0}, hi = {0, 0, 0};
    std::vector<VoxelIndex> cells;
    cells.reserve(reference_size);
    for (uint64_t key : data.reference.keys) cells.push_back(UnpackVoxel(key));
    for (size_t i = 0; i < cells.size(); ++i) {
      for (int a = 0; a < 3; ++a) {
        lo[a] = i == 0 ? cells[i][a] : std::min(lo[a], cells[i][a]);
        hi[a] = i == 0 ? cells[i][a] : std::max(hi[a], cells[i][a]);
      }
    }
    const bool is_small = hi[0] - lo[0] < 65536 && hi[1] - lo[1] < 65536 && hi[2] - lo[2] < 65536;
    std::string index_b64;
    if (is_small) {
      std::vector<uint16_t> index(3 * cells.size());
      for (size_t i = 0; i < cells.size(); ++i)
        for (int a = 0; a < 3; ++a) index[3 * i + a] = static_cast<uint16_t>(cells[i][a] - lo[a]);
      index_b64 = Base64(index);
    } else {
      std::vector<int32_t> index(3 * cells.size());
      for (size_t i = 0; i < cells.size(); ++i)
        for (int a = 0; a < 3; ++a) index[3 * i + a] = static_cast<int32_t>(cells[i][a] - lo[a]);
      index_b64 = Base64(index);
    }
    voxels = {{"count", reference_size},
              {"cell_size", data.reference.cell_size},
              {"origin", ordered_json::array({lo[0], lo[1], lo[2]})},
              {"index_type", is_small ? "u16" : "i32"},
              {"index", std::move(index_b64)},
              {"seen", Base64(seen)}};
  }

  // Meshes.
  std::string mesh_note;
  const std::vector<TriangleMesh> meshes =
      PageMeshes(scene, options.max_mesh_triangles, &mesh_note);
  if (!mesh_note.empty()) notes.push_back(mesh_note);
  if (scene.objects.empty())
    notes.emplace_back(
        "The scene's meshes were not available when this page was written; the 3D view shows "
        "voxels and sensors only.");
  ordered_json meshes_json = ordered_json::array();
  for (size_t i = 0; i < meshes.size() && i < scene.objects.size(); ++i) {
    const TriangleMesh& mesh = meshes[i];
    if (mesh.IsEmpty()) continue;
    std::vector<float> positions;
    positions.reserve(3 * mesh.vertices.size());
    for (const Vec3& v : mesh.vertices)
      for (int a = 0; a < 3; ++a) positions.push_back(static_cast<float>(v[a]));
    std::vector<uint32_t> indices;
    indices.reserve(3 * mesh.triangles.size());
    for (const auto& t : mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
    meshes_json.push_back({{"name", scene.objects[i].name},
                           {"target", scene.objects[i].is_target()},
                           {"positions", Base64(positions)},
                           {"indices", Base64(indices)}});
  }

  // three.js, read now and inlined; without it the page says why there is no 3D view.
  std::string three, orbit;
  const std::string three_path = options.three_js_dir + "/three.min.js";
  const std::string orbit_path = options.three_js_dir + "/examples/js/controls/OrbitControls.js";
  const bool has_three =
      ReadFile(three_path, &three) && ReadFile(orbit_path, &orbit) && !three.empty();
  std::string three_note;
  if (!has_three)
    three_note = fmt::format(
        "The 3D view is not available: three.js r111 was not found at {} and {} when this "
        "page was written. Install Debian's libjs-three and run vantage again.",
        three_path, orbit_path);

  const double fov = 0.7853981633974483;
  const View view = DefaultView(scene, report, fov);

  page["meta"] = {{"scene", report.scene},
                  {"version", Version()},
                  {"seed", report.seed},
                  {"cell_size", data.reference.cell_size},
                  {"reference_voxels", reference_size}};
  if (primary >= 0) {
    const Selection& s = report.results[static_cast<size_t>(primary)];
    page["primary"] = {
        {"index", primary}, {"method", s.method}, {"n", s.n}, {"coverage", s.coverage}};
  } else {
    page["primary"] = nullptr;
  }
  page["view"] = {
      {"eye", Vec3Json(view.eye)}, {"look_at", Vec3Json(view.look_at)}, {"fov_deg", 45.0}};
  page["colors"] = {
      {"unobserved", RgbJson(kUnobservedColor)},
      {"observed", ordered_json::array({RgbJson(kObservedColors[0]), RgbJson(kObservedColors[1]),
                                        RgbJson(kObservedColors[2])})},
      {"occluder", RgbJson(kOccluderColor)},
      {"frustum", RgbJson(kFrustumColor)}};
  page["notes"] = notes;
  page["three_note"] = three_note;
  page["candidates"] = std::move(candidates);
  page["results"] = std::move(results);
  page["chosen"] = std::move(chosen_json);
  page["quality"] = data.quality.active();
  if (report.states) {
    ordered_json names = ordered_json::array();
    for (const StatesInfo::State& state : report.states->states) names.push_back(state.name);
    page["states"] = {{"over", report.states->over}, {"names", std::move(names)}};
  } else {
    page["states"] = nullptr;
  }
  if (report.robustness) {
    // The same keys as report.json's "robustness" (sensor names, not indices).
    page["robustness"] = ordered_json::parse(RobustnessJsonText(*report.robustness, data));
  } else {
    page["robustness"] = nullptr;
  }
  page["voxels"] = std::move(voxels);
  page["meshes"] = std::move(meshes_json);

  std::string subtitle =
      fmt::format("{} · {} reference voxels of {} m · {} candidates", report.scene, reference_size,
                  data.reference.cell_size, data.candidates.size());
  if (primary >= 0) {
    const Selection& s = report.results[static_cast<size_t>(primary)];
    subtitle += fmt::format(" · {} N = {}: {:.2f} %", s.method, s.n, 100.0 * s.coverage);
  }
  const std::string title = "vantage report";

  std::string html = kPageHead;
  const auto replace_all = [&html](const std::string& what, const std::string& with) {
    size_t at = 0;
    while ((at = html.find(what, at)) != std::string::npos) {
      html.replace(at, what.size(), with);
      at += with.size();
    }
  };
  replace_all("@TITLE@", detail::MarkupEscape(title));
  replace_all("@SUBTITLE@", detail::MarkupEscape(subtitle));
  if (has_three) {
    html += "<script>\n" + ScriptSafe(three) + "\n</script>\n";
    html += "<script>\n" + ScriptSafe(orbit) + "\n</script>\n";
  }
  html += R"(<script id="vantage-data" type="application/json">)" + JsonScriptSafe(page.dump()) +
          "</script>\n";
  html += "<script>";
  html += kPageScript;
  html += "</script>\n</body>\n</html>\n";
  return html;
}

}  // namespace vantage
