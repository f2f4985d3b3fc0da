// report.html (issue #7; docs/outputs.md): one self-contained page. three.js r111 from Debian's
// libjs-three is read at run time and inlined, the data is embedded as JSON (bulk arrays as
// base64 typed arrays), the chart and the sortable tables are drawn by the page's own small
// script. The page's HTML, CSS and script are files in src/report/assets/, compiled in (CMake,
// cmake/EmbedFiles.cmake). Nothing is fetched: the page opens from disk without network access.
#include <fmt/format.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <functional>
#include <iterator>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string_view>

#include "embedded/report_assets.hpp"
#include "report/by_type_json.hpp"
#include "report/constraints_json.hpp"
#include "util/markup.hpp"
#include "util/words.hpp"
#include "vantage/error.hpp"
#include "vantage/reference.hpp"
#include "vantage/visualize.hpp"

namespace vantage {
namespace {

using nlohmann::ordered_json;

// ---------------------------------------------------------------------------------------------
// The page: src/report/assets/report.html, with report.css and report.js, embedded at build time.

// One placeholder's value: appended to the page where @NAME@ stands.
struct TemplateValue {
  std::string_view name;
  std::function<void(std::string*)> append;
};

// Appends the page with each @NAME@ of the template replaced by its value in one pass (values
// are not searched again, so inlined scripts may hold any text). Every placeholder must have a
// value.
void FillTemplate(std::string_view page, const std::vector<TemplateValue>& values,
                  std::string* out) {
  size_t at = 0;
  while (true) {
    const size_t open = page.find('@', at);
    if (open == std::string_view::npos) break;
    const size_t close = page.find('@', open + 1);
    VANTAGE_CHECK(close != std::string_view::npos);
    const std::string_view name = page.substr(open + 1, close - open - 1);
    const auto it = std::find_if(values.begin(), values.end(),
                                 [&](const TemplateValue& value) { return value.name == name; });
    VANTAGE_CHECK(it != values.end());
    out->append(page.substr(at, open - at));
    it->append(out);
    at = close + 1;
  }
  out->append(page.substr(at));
}

// ---------------------------------------------------------------------------------------------

std::string Base64(const void* bytes, size_t size) {
  static constexpr std::string_view kAlphabet =
      "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* in = static_cast<const uint8_t*>(bytes);
  // Written into the string's own buffer (appending a character at a time was a tenth of the
  // page's time on the occlusion world).
  std::string out((size + 2) / 3 * 4, '=');
  char* o = out.data();
  size_t i = 0;
  for (; i + 2 < size; i += 3, o += 4) {
    const uint32_t v = (uint32_t{in[i]} << 16) | (uint32_t{in[i + 1]} << 8) | in[i + 2];
    o[0] = kAlphabet[(v >> 18) & 63];
    o[1] = kAlphabet[(v >> 12) & 63];
    o[2] = kAlphabet[(v >> 6) & 63];
    o[3] = kAlphabet[v & 63];
  }
  if (i + 1 == size) {  // "xx=="
    const uint32_t v = uint32_t{in[i]} << 16;
    o[0] = kAlphabet[(v >> 18) & 63];
    o[1] = kAlphabet[(v >> 12) & 63];
  } else if (i + 2 == size) {  // "xxx="
    const uint32_t v = (uint32_t{in[i]} << 16) | (uint32_t{in[i + 1]} << 8);
    o[0] = kAlphabet[(v >> 18) & 63];
    o[1] = kAlphabet[(v >> 12) & 63];
    o[2] = kAlphabet[(v >> 6) & 63];
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
void AppendScriptSafe(std::string_view text, std::string* out) {
  // Copied in runs up to each '<' (three.js alone is 850 kB: a character at a time was slow).
  size_t from = 0;
  for (size_t i = text.find('<'); i != std::string_view::npos; i = text.find('<', i + 1)) {
    out->append(text.substr(from, i + 1 - from));
    from = i + 1;
    const std::string_view rest = text.substr(i + 1);
    const bool is_close =
        rest.size() >= 7 && rest[0] == '/' &&
        std::equal(rest.begin() + 1, rest.begin() + 7, "script",
                   [](char a, char b) { return std::tolower(static_cast<unsigned char>(a)) == b; });
    if (is_close || rest.substr(0, 3) == "!--") *out += '\\';
  }
  out->append(text.substr(from));
}

// JSON for a <script type="application/json"> element: '<' only occurs inside strings, where
// \u003c means the same and can never start a tag.
void AppendJsonScriptSafe(std::string_view json, std::string* out) {
  size_t from = 0;
  for (size_t i = json.find('<'); i != std::string_view::npos; i = json.find('<', i + 1)) {
    out->append(json.substr(from, i - from));
    *out += "\\u003c";
    from = i + 1;
  }
  out->append(json.substr(from));
}

// The page's bulk arrays (base64: meshes, voxels, what-if sets) are kept out of the JSON tree
// while it is built: each stands there as a token naming it, and the serialised text gets the
// blob where its token is (nlohmann's dump escapes a string a character at a time: 1.3 MB of
// meshes on the occlusion world). A token is a JSON string that dump writes as
// "\u0001vantage-blob-N\u0002"; where the text holds any other such token (a name with those
// control characters), the page is built again with the blobs inline.
class Blobs {
 public:
  explicit Blobs(bool inline_blobs) : inline_(inline_blobs) {}

  ordered_json Add(std::string base64) {
    if (inline_) return base64;
    blobs_.push_back(std::move(base64));
    return fmt::format("\x01vantage-blob-{}\x02", blobs_.size() - 1);
  }

  size_t bytes() const {
    size_t size = 0;
    for (const std::string& blob : blobs_) size += blob.size();
    return size;
  }

  // Appends `json` (dumped) made script-safe with each token replaced by its blob; false,
  // appending nothing, when the tokens found are not each blob exactly once.
  bool AppendJson(std::string_view json, std::string* out) const {
    if (inline_) {
      AppendJsonScriptSafe(json, out);
      return true;
    }
    static constexpr std::string_view kOpen = "\"\\u0001vantage-blob-";
    static constexpr std::string_view kClose = "\\u0002\"";
    struct Found {
      size_t at, end, blob;
    };
    std::vector<Found> found;
    std::vector<char> used(blobs_.size(), 0);
    for (size_t at = json.find(kOpen); at != std::string_view::npos;
         at = json.find(kOpen, at + 1)) {
      size_t digits = at + kOpen.size();
      size_t blob = 0;
      size_t end = digits;
      while (end < json.size() && json[end] >= '0' && json[end] <= '9' && end - digits < 18)
        blob = blob * 10 + static_cast<size_t>(json[end++] - '0');
      if (end == digits || json.substr(end, kClose.size()) != kClose || blob >= blobs_.size() ||
          used[blob])
        return false;
      used[blob] = 1;
      found.push_back({at, end + kClose.size(), blob});
    }
    if (found.size() != blobs_.size()) return false;
    size_t from = 0;
    for (const Found& f : found) {
      AppendJsonScriptSafe(json.substr(from, f.at - from), out);
      *out += '"';
      out->append(blobs_[f.blob]);  // base64: nothing to escape, no '<'
      *out += '"';
      from = f.end;
    }
    AppendJsonScriptSafe(json.substr(from), out);
    return true;
  }

 private:
  bool inline_;
  std::vector<std::string> blobs_;
};

// Vertex clustering: vertices in one cell of size `cell` merge into their mean; triangles that
// collapse or repeat are dropped. Keeps the silhouette of huge meshes at a bounded size.
// By sorting, not by hash map and tree (PageMeshes clusters millions of vertices in each of its
// rounds); clusters are numbered by their first vertex and a repeated triangle is kept where it
// first occurs, as one scan in index order would.
TriangleMesh ClusterVertices(const TriangleMesh& mesh, double cell) {
  const size_t vertex_count = mesh.vertices.size();
  if (vertex_count == 0) return {};
  VANTAGE_CHECK(vertex_count <= std::numeric_limits<uint32_t>::max());
  std::vector<std::array<int64_t, 3>> cell_index(vertex_count);
  std::array<int64_t, 3> lowest;
  lowest.fill(std::numeric_limits<int64_t>::max());
  for (size_t i = 0; i < vertex_count; ++i) {
    for (int a = 0; a < 3; ++a) {
      cell_index[i][a] = static_cast<int64_t>(std::floor(mesh.vertices[i][a] / cell));
      lowest[a] = std::min(lowest[a], cell_index[i][a]);
    }
  }
  // Each vertex's cell as one 63-bit key: the cell is at least 1/4096 of the scene's diagonal, so
  // an object spans at most 4098 cells along an axis, well within 21 bits.
  constexpr int kBitsPerAxis = 21;
  std::vector<std::pair<uint64_t, uint32_t>> by_cell(vertex_count);
  for (size_t i = 0; i < vertex_count; ++i) {
    uint64_t key = 0;
    for (int a = 0; a < 3; ++a) {
      const int64_t offset = cell_index[i][a] - lowest[a];
      VANTAGE_CHECK(offset < (int64_t{1} << kBitsPerAxis));
      key = (key << kBitsPerAxis) | static_cast<uint64_t>(offset);
    }
    by_cell[i] = {key, static_cast<uint32_t>(i)};
  }
  std::sort(by_cell.begin(), by_cell.end());
  // One run of by_cell per cell, its first vertex first; clusters numbered in that vertex's order.
  std::vector<std::pair<uint32_t, size_t>> first_vertex_and_run;
  for (size_t start = 0; start < vertex_count;) {
    size_t end = start + 1;
    while (end < vertex_count && by_cell[end].first == by_cell[start].first) ++end;
    first_vertex_and_run.emplace_back(by_cell[start].second, start);
    start = end;
  }
  std::sort(first_vertex_and_run.begin(), first_vertex_and_run.end());
  std::vector<uint32_t> cluster(vertex_count);
  for (size_t c = 0; c < first_vertex_and_run.size(); ++c) {
    const size_t start = first_vertex_and_run[c].second;
    for (size_t k = start; k < vertex_count && by_cell[k].first == by_cell[start].first; ++k)
      cluster[by_cell[k].second] = static_cast<uint32_t>(c);
  }
  TriangleMesh out;
  std::vector<int> counts(first_vertex_and_run.size(), 0);
  out.vertices.assign(first_vertex_and_run.size(), Vec3::Zero());
  for (size_t i = 0; i < vertex_count; ++i) {  // summed in index order: the means do not depend
    out.vertices[cluster[i]] += mesh.vertices[i];  // on the sort
    ++counts[cluster[i]];
  }
  for (size_t c = 0; c < counts.size(); ++c) out.vertices[c] = out.vertices[c] / counts[c];

  // Triangles by their sorted corners, then by position: the first of each run is kept.
  std::vector<std::pair<std::array<uint32_t, 3>, size_t>> by_corners;
  by_corners.reserve(mesh.triangles.size());
  for (size_t j = 0; j < mesh.triangles.size(); ++j) {
    const auto& t = mesh.triangles[j];
    std::array<uint32_t, 3> c = {cluster[t[0]], cluster[t[1]], cluster[t[2]]};
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
    std::sort(c.begin(), c.end());
    by_corners.emplace_back(c, j);
  }
  std::sort(by_corners.begin(), by_corners.end());
  std::vector<char> kept(mesh.triangles.size(), 0);
  for (size_t k = 0; k < by_corners.size(); ++k) {
    if (k == 0 || by_corners[k].first != by_corners[k - 1].first) kept[by_corners[k].second] = 1;
  }
  for (size_t j = 0; j < mesh.triangles.size(); ++j) {
    if (!kept[j]) continue;
    const auto& t = mesh.triangles[j];
    out.triangles.push_back({cluster[t[0]], cluster[t[1]], cluster[t[2]]});
  }
  return out;
}

// The meshes embedded in the page: the scene's own, or simplified until they fit the budget.
// The cells grow by 1.4 a round from 1/4096 of the scene's diagonal; the page takes the smallest
// that fits, found by bisection over the 40 rounds since each round clusters every vertex of the
// scene. Larger cells leave fewer triangles all but always; where the grid cuts a shape so that
// they do not, the bisection still ends on a round that fits, one or two rounds coarser.
// Empty when the scene's own meshes fit (they are not copied).
std::vector<TriangleMesh> PageMeshes(const Scene& scene, size_t max_triangles, std::string* note) {
  const size_t total = scene.TriangleCount();
  if (total <= max_triangles) return {};
  Aabb bounds;
  for (const SceneObject& object : scene.objects) {
    if (!object.mesh.IsEmpty()) bounds.Extend(object.mesh.Bounds());
  }
  const double diagonal = (bounds.max - bounds.min).norm();
  constexpr int kRounds = 40;
  const auto cell_of_round = [&](int round) {
    double cell = diagonal / 4096.0;
    for (int r = 0; r < round; ++r) cell *= 1.4;
    return cell;
  };
  struct Simplified {
    std::vector<TriangleMesh> meshes;
    size_t triangles = 0;
  };
  const auto simplify = [&](int round) {
    Simplified out;
    for (const SceneObject& object : scene.objects) {
      out.meshes.push_back(ClusterVertices(object.mesh, cell_of_round(round)));
      out.triangles += out.meshes.back().triangles.size();
    }
    return out;
  };
  // Invariant: every round below `low` leaves too many triangles; round `high` fits (or is the last).
  int low = 0;
  int high = kRounds - 1;
  Simplified fitting;
  while (low < high) {
    const int middle = (low + high) / 2;
    Simplified trial = simplify(middle);
    if (trial.triangles <= max_triangles) {
      high = middle;
      fitting = std::move(trial);
    } else {
      low = middle + 1;
    }
  }
  if (fitting.meshes.empty()) fitting = simplify(high);  // high was never tried: the last round
  *note = fmt::format(
      "The 3D view shows the meshes simplified from {} to {} triangles "
      "(vertex clustering, {:.3g} m cells); pictures and numbers use the full meshes.",
      total, fitting.triangles, cell_of_round(high));
  return std::move(fitting.meshes);
}

// ---------------------------------------------------------------------------------------------
// The what-if sets (issue 46): each candidate's observed cells of R, compact, so that the page
// can score any layout the reader clicks together. Per candidate a varint (count << 1 | mode)
// then, mode 0, `count` varints of the gaps between its sorted indices (index - previous - 1,
// previous = -1 at first); mode 1, a bitset of |R| bits (LSB first), whichever is shorter.

void AppendVarint(uint64_t value, std::string* out) {
  while (value >= 0x80) {
    out->push_back(static_cast<char>((value & 0x7F) | 0x80));
    value >>= 7;
  }
  out->push_back(static_cast<char>(value));
}

size_t VarintSize(uint64_t value) {
  size_t size = 1;
  for (; value >= 0x80; value >>= 7) ++size;
  return size;
}

std::string EncodeSets(const std::vector<Observation>& observations, size_t cells) {
  std::string out;
  const size_t bitset_bytes = (cells + 7) / 8;
  for (const Observation& o : observations) {
    const std::vector<uint32_t>& indices = o.reference_indices;
    size_t list_bytes = 0;
    int64_t previous = -1;
    for (const uint32_t r : indices) {
      list_bytes += VarintSize(static_cast<uint64_t>(static_cast<int64_t>(r) - previous - 1));
      previous = r;
    }
    const bool as_bitset = bitset_bytes < list_bytes;
    AppendVarint((uint64_t{indices.size()} << 1) | (as_bitset ? 1u : 0u), &out);
    if (as_bitset) {
      std::string bits(bitset_bytes, '\0');
      for (const uint32_t r : indices) bits[r / 8] = static_cast<char>(bits[r / 8] | (1 << (r % 8)));
      out += bits;
    } else {
      previous = -1;
      for (const uint32_t r : indices) {
        AppendVarint(static_cast<uint64_t>(static_cast<int64_t>(r) - previous - 1), &out);
        previous = r;
      }
    }
  }
  return out;
}

// The part (target object) each cell of R belongs to: the first target, in the scene's order,
// whose triangles touch it (BuildReference's cells, so every cell of R has one when the scene is
// the run's); -1 for none. Empty without the scene's meshes.
std::vector<int32_t> CellParts(const Scene& scene, const Reference& reference,
                               std::vector<std::string>* names) {
  // R's own parts, where they are the target objects one to one (the same names in the same
  // order, so each object its own part): BuildReference gave each cell the first of them whose
  // triangles touch it, the rule below, so its part_of saves clipping every target triangle
  // again (issue 47: a third of the page's time on the occlusion world).
  std::vector<std::string> target_names;
  bool meshes = true;  // a scene without its meshes (select's, not found) names no part
  for (const SceneObject& object : scene.objects) {
    if (!object.is_target()) continue;
    target_names.push_back(object.name);
    meshes = meshes && !object.mesh.IsEmpty();
  }
  const bool parts_are_objects =
      meshes && target_names == reference.part_names && reference.part_of.size() == reference.size() &&
      std::all_of(reference.part_of.begin(), reference.part_of.end(),
                  [&](uint32_t p) { return p < target_names.size(); });
  if (parts_are_objects) {
    // Only the parts holding a cell are named, in scene order.
    std::vector<int32_t> index_of(target_names.size(), -1);
    for (const uint32_t p : reference.part_of) index_of[p] = 0;
    for (size_t p = 0; p < index_of.size(); ++p) {
      if (index_of[p] < 0) continue;
      index_of[p] = static_cast<int32_t>(names->size());
      names->push_back(target_names[p]);
    }
    std::vector<int32_t> part(reference.size(), -1);
    for (size_t r = 0; r < part.size(); ++r) part[r] = index_of[reference.part_of[r]];
    if (names->empty()) part.clear();
    return part;
  }
  std::vector<int32_t> part(reference.size(), -1);
  std::vector<uint64_t> keys;
  for (const SceneObject& object : scene.objects) {
    if (!object.is_target() || object.mesh.IsEmpty()) continue;
    keys.clear();
    const TriangleMesh& mesh = object.mesh;
    for (const auto& t : mesh.triangles)
      AppendTriangleCells(mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]],
                          reference.cell_size, &keys);
    std::sort(keys.begin(), keys.end());
    keys.erase(std::unique(keys.begin(), keys.end()), keys.end());
    const int32_t index = static_cast<int32_t>(names->size());
    bool any = false;
    for (const uint64_t key : keys) {
      const int64_t r = reference.IndexOf(key);
      if (r < 0 || part[static_cast<size_t>(r)] >= 0) continue;
      part[static_cast<size_t>(r)] = index;
      any = true;
    }
    if (any) names->push_back(object.name);
  }
  if (names->empty()) part.clear();
  return part;
}

ordered_json Vec3Json(const Vec3& v) { return ordered_json::array({v.x(), v.y(), v.z()}); }
ordered_json RgbJson(const Rgb& c) { return ordered_json::array({c[0], c[1], c[2]}); }

// The page's what-if data, or null with a note saying why there is none.
ordered_json WhatIfJson(const Report& report, const Scene& scene, const HtmlReportOptions& options,
                        Blobs* blobs, std::vector<std::string>* notes) {
  const VisibilityFile& data = *report.data;
  const size_t cells = data.reference.size();
  if (report.states) {
    notes->emplace_back(
        "The what-if layout is not offered over scene states (a layout's coverage is per state).");
    return nullptr;
  }
  if (cells == 0 || data.candidates.empty()) return nullptr;
  // The page decodes every set into a bitset of |R| bits.
  const double decoded = static_cast<double>(data.candidates.size()) *
                         static_cast<double>((cells + 31) / 32 * 4);
  if (decoded > static_cast<double>(options.max_whatif_bytes)) {
    notes->push_back(fmt::format(
        "The what-if layout is not offered: {} candidates x {} cells would take {:.0f} MB in the "
        "browser, above the {:.0f} MB the page allows.",
        data.candidates.size(), cells, decoded / 1e6,
        static_cast<double>(options.max_whatif_bytes) / 1e6));
    return nullptr;
  }
  const std::string sets = EncodeSets(data.observations, cells);
  if (sets.size() > options.max_whatif_bytes) {
    notes->push_back(fmt::format(
        "The what-if layout is not offered: the candidates' sets take {:.0f} MB, above the {:.0f} "
        "MB the page allows.",
        static_cast<double>(sets.size()) / 1e6,
        static_cast<double>(options.max_whatif_bytes) / 1e6));
    return nullptr;
  }
  ordered_json whatif = {{"cells", cells}, {"sets", blobs->Add(Base64(sets.data(), sets.size()))}};
  std::vector<std::string> names;
  const std::vector<int32_t> part = CellParts(scene, data.reference, &names);
  if (!part.empty()) {
    std::vector<uint16_t> part16(part.size());
    std::vector<size_t> part_cells(names.size(), 0);
    for (size_t r = 0; r < part.size(); ++r) {
      part16[r] = part[r] < 0 ? uint16_t{65535} : static_cast<uint16_t>(std::min(part[r], 65534));
      if (part[r] >= 0) ++part_cells[static_cast<size_t>(part[r])];
    }
    ordered_json parts = ordered_json::array();
    for (size_t k = 0; k < names.size(); ++k)
      parts.push_back({{"name", names[k]}, {"cells", part_cells[k]}});
    whatif["parts"] = std::move(parts);
    whatif["cell_part"] = blobs->Add(Base64(part16));
  }
  const int primary = report.primary;
  if (primary >= 0 && report.results[static_cast<size_t>(primary)].min_points)
    whatif["note"] = fmt::format(
        "counts a cell once any sensor sees it; the run's coverage counts cells with >= {} points",
        *report.results[static_cast<size_t>(primary)].min_points);
  return whatif;
}

// The page, its bulk arrays as `blobs` says; nullopt when a token of theirs is ambiguous.
std::optional<std::string> BuildPage(const Report& report, const Scene& scene,
                                     const HtmlReportOptions& options, Blobs* blobs) {
  VANTAGE_CHECK(report.data != nullptr);
  VANTAGE_CHECK(options.max_mesh_triangles >= 1);
  const VisibilityFile& data = *report.data;
  const size_t reference_size = data.reference.keys.size();
  const auto fraction = [&](size_t count) {
    return reference_size ? static_cast<double>(count) / static_cast<double>(reference_size) : 0.0;
  };
  VANTAGE_CHECK(report.is_derived);
  const int primary = report.primary;

  ordered_json page;
  std::vector<std::string> notes = report.notes;

  // The default view's framing probes the scene's surface from a few looks; it runs beside the
  // page's other parts, which need it only for the candidates' frustum depths and the view
  // (issue 47: a third of the page's time, on the run's last serial stretch).
  Framing framing;
  tbb::task_group framing_task;
  framing_task.run([&] { framing = DefaultFraming(scene, report); });
  // Candidates ("depth" is filled in once the framing is known).
  ordered_json candidates = ordered_json::array();
  for (size_t i = 0; i < data.candidates.size(); ++i) {
    const Candidate& c = data.candidates[i];
    const Observation& o = data.observations.at(i);
    const SensorType& s = c.sensor;
    candidates.push_back(
        {{"name", c.name},
         {"type", c.type_id.empty() ? s.id : c.type_id},
         {"population", c.population},
         {"p", Vec3Json(c.world_from_body.position)},
         {"q", WxyzOf(c.world_from_body.rotation)},
         {"w", s.width},
         {"h", s.height},
         {"fx", s.fx},
         {"fy", s.fy},
         {"cx", s.cx},
         {"cy", s.cy},
         {"near", s.near},
         {"far", s.far},
         {"depth", 0.0},
         {"observed", o.reference_indices.size()},
         {"coverage", fraction(o.reference_indices.size())},
         {"paper_coverage", fraction(o.reference_indices.size() + o.outside_keys.size())}});
  }

  // Results, and the coverage curve's extra answers (report.json `curve`).
  const auto result_json = [](const Selection& s) {
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
    if (!s.state_coverage.empty()) r["state_coverage"] = s.state_coverage;
    if (s.cost) r["cost"] = *s.cost;  // a budget or --cheapest: the robustness table's costs
    return r;
  };
  // A camera on an arm (issue 45): each answer's tour time, home to home (the chart of coverage
  // versus seconds); absent without a tour.
  const auto add_tour_seconds = [](const std::vector<std::optional<ArmTour>>& tours, size_t index,
                                   ordered_json* r) {
    if (index < tours.size() && tours[index] && tours[index]->tour.connected())
      (*r)["tour_seconds"] = tours[index]->tour.total_seconds;
  };
  ordered_json results = ordered_json::array();
  for (size_t index = 0; index < report.results.size(); ++index) {
    results.push_back(result_json(report.results[index]));
    if (!report.result_plain_coverage.empty())
      results.back()["plain_coverage"] = report.result_plain_coverage[index];
    add_tour_seconds(report.tours, index, &results.back());
  }
  ordered_json curve = ordered_json::array();
  for (size_t index = 0; index < report.curve.size(); ++index) {
    curve.push_back(result_json(report.curve[index]));
    add_tour_seconds(report.curve_tours, index, &curve.back());
  }
  page["cycle_time"] = report.cycle_time ? ordered_json(*report.cycle_time) : ordered_json();

  // Chosen sensors in the order chosen, with their marginal gains (derived), and per reference
  // voxel how many of them observe it (the page's colours).
  std::vector<uint8_t> seen(reference_size, 0);
  ordered_json chosen_json = ordered_json::array();
  for (const ChosenSensor& sensor : report.primary_sensors) {
    for (uint32_t r : data.observations[sensor.index].reference_indices) {
      if (seen[r] < 255) ++seen[r];
    }
    const Vec3 rpy = RpyFromRotation(
        data.candidates[sensor.index].world_from_body.rotation.normalized().toRotationMatrix());
    chosen_json.push_back({{"index", sensor.index},
                           {"marginal_gain", sensor.marginal_gain},
                           {"cumulative", sensor.cumulative},
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
              {"index", blobs->Add(std::move(index_b64))},
              {"seen", blobs->Add(Base64(seen))}};
  }

  // Meshes.
  std::string mesh_note;
  const std::vector<TriangleMesh> simplified =
      PageMeshes(scene, options.max_mesh_triangles, &mesh_note);
  std::vector<const TriangleMesh*> meshes;
  for (size_t i = 0; i < scene.objects.size(); ++i)
    meshes.push_back(simplified.empty() ? &scene.objects[i].mesh : &simplified[i]);
  if (!mesh_note.empty()) notes.push_back(mesh_note);
  if (scene.objects.empty())
    notes.emplace_back(
        "The scene's meshes were not available when this page was written; the 3D view shows "
        "voxels and sensors only.");
  ordered_json meshes_json = ordered_json::array();
  for (size_t i = 0; i < meshes.size() && i < scene.objects.size(); ++i) {
    const TriangleMesh& mesh = *meshes[i];
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
                           {"positions", blobs->Add(Base64(positions))},
                           {"indices", blobs->Add(Base64(indices))}});
  }

  // three.js, read now and inlined; without it the page says why there is no 3D view.
  std::string three, orbit;
  const std::string three_path = options.three_js_dir + "/three.min.js";
  const std::string orbit_path = options.three_js_dir + "/examples/js/controls/OrbitControls.js";
  const bool has_three =
      detail::ReadWholeFile(three_path, &three) && detail::ReadWholeFile(orbit_path, &orbit) &&
      !three.empty();
  std::string three_note;
  if (!has_three)
    three_note = fmt::format(
        "The 3D view is not available: three.js r111 was not found at {} and {} when this "
        "page was written. Install Debian's libjs-three and run vantage again.",
        three_path, orbit_path);

  framing_task.wait();
  for (size_t i = 0; i < data.candidates.size(); ++i)
    candidates[i]["depth"] = FrustumDepth(data.candidates[i], framing.targets);
  // The page fits the default view again for its canvas' aspect (report.js, fitView); the eye
  // given here is FitView's for the view's usual 2.5 : 1.
  const double fov = 0.7853981633974483;
  const View view = FramedView(framing, fov, 2.5);
  for (size_t k = 0; k < chosen_json.size(); ++k) {
    const Candidate& c = data.candidates.at(report.primary_sensors[k].index);
    chosen_json[k]["frustum_depth"] = FrustumDepth(c, framing.targets);
  }
  ordered_json framed = ordered_json::array();
  for (const Vec3& p : framing.sensors) framed.push_back(Vec3Json(p));

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
  page["view"] = {{"eye", Vec3Json(view.eye)},
                  {"look_at", Vec3Json(view.look_at)},
                  {"fov_deg", 45.0},
                  {"direction", Vec3Json(framing.direction)},
                  {"targets", ordered_json::array({Vec3Json(framing.targets.min),
                                                   Vec3Json(framing.targets.max)})},
                  {"sensors", std::move(framed)}};
  ordered_json method_colors = ordered_json::object();
  for (const MethodColorEntry& entry : kMethodColors)
    method_colors[std::string(entry.method)] = RgbJson(entry.color);
  page["colors"] = {
      {"unobserved", RgbJson(kUnobservedColor)},
      {"observed", ordered_json::array({RgbJson(kObservedColors[0]), RgbJson(kObservedColors[1]),
                                        RgbJson(kObservedColors[2])})},
      {"occluder", RgbJson(kOccluderColor)},
      {"frustum", RgbJson(kFrustumColor)},
      {"methods", std::move(method_colors)},
      {"other_method", RgbJson(kOtherMethodColor)}};
  ordered_json whatif = WhatIfJson(report, scene, options, blobs, &notes);
  page["notes"] = notes;
  page["three_note"] = three_note;
  page["candidates"] = std::move(candidates);
  page["results"] = std::move(results);
  page["curve"] = std::move(curve);
  // optimize --by-type (issue 43): each sensor type alone per N beside the mix, as report.json.
  page["by_type"] = report.by_type ? detail::ByTypeJson(*report.by_type, data) : ordered_json();
  page["chosen"] = std::move(chosen_json);
  // The primary result's overlap graph (docs/constraints.md): lines between the chosen sensors
  // that share cells, under the calibration rule when there is one.
  if (report.constraints && report.primary >= 0) {
    ordered_json overlap = ordered_json::array();
    for (const OverlapEdge& e : CheckConstraints(data.observations, report.PrimaryChosen(),
                                                 report.constraints->constraints)
                                    .edges)
      overlap.push_back({{"a", e.a}, {"b", e.b}, {"cells", e.cells}});
    page["overlap"] = std::move(overlap);
  }
  // The scene's keep-out boxes (docs/constraints.md, Mounting rules), drawn posed in the 3D view.
  if (report.constraints && !report.constraints->keep_out_boxes.empty()) {
    ordered_json boxes = ordered_json::array();
    for (const KeepOutBox& box : report.constraints->keep_out_boxes)
      boxes.push_back(detail::KeepOutBoxJson(box));
    page["keep_out"] = std::move(boxes);
  }
  // A camera on an arm (issue 45): the primary result's tour — each stop's links (ghosted in the
  // 3D view, each link's mesh once, posed per stop), the camera's path and the time line.
  page["arm"] = nullptr;
  if (primary >= 0 && static_cast<size_t>(primary) < report.tours.size() &&
      report.tours[static_cast<size_t>(primary)]) {
    const ArmTour& tour = *report.tours[static_cast<size_t>(primary)];
    ordered_json arm;
    arm["robot"] = tour.robot;
    arm["method"] = tour.tour.method;
    arm["exact"] = tour.tour.exact;
    arm["seconds"] = tour.tour.connected() ? ordered_json(tour.tour.total_seconds) : ordered_json();
    arm["return_seconds"] = std::isfinite(tour.return_seconds) ? ordered_json(tour.return_seconds)
                                                                : ordered_json();
    ordered_json links = ordered_json::array(), stops = ordered_json::array();
    std::shared_ptr<const ArmBody> body;
    for (size_t k = 0; k < tour.views.size(); ++k) {
      const Candidate& c = data.candidates.at(tour.views[k]);
      ordered_json stop;
      stop["name"] = c.name;
      if (k < tour.states.size()) stop["state"] = tour.states[k];
      stop["move_seconds"] = std::isfinite(tour.move_seconds[k]) ? ordered_json(tour.move_seconds[k])
                                                                 : ordered_json();
      stop["acquisition_seconds"] = tour.acquisition_seconds[k];
      stop["planned"] = k < tour.move_via.size() && !tour.move_via[k].empty();
      stop["camera"] = Vec3Json(c.world_from_body.position);
      ordered_json poses = ordered_json::array();
      if (c.arm && c.arm->body) {
        if (!body) body = c.arm->body;
        if (c.arm->body == body) {
          for (const Pose& pose : c.arm->world_from_link)
            poses.push_back({pose.position.x(), pose.position.y(), pose.position.z(),
                             pose.rotation.w(), pose.rotation.x(), pose.rotation.y(),
                             pose.rotation.z()});
        }
      }
      stop["links"] = std::move(poses);  // xyz, quaternion wxyz per link of `links`
      stops.push_back(std::move(stop));
    }
    if (body) {
      for (size_t l = 0; l < body->links.size(); ++l) {
        const TriangleMesh& mesh = body->link_meshes[l];
        std::vector<float> positions;
        for (const Vec3& v : mesh.vertices)
          for (int a = 0; a < 3; ++a) positions.push_back(static_cast<float>(v[a]));
        std::vector<uint32_t> indices;
        for (const auto& t : mesh.triangles) indices.insert(indices.end(), t.begin(), t.end());
        links.push_back({{"name", body->links[l]},
                         {"positions", blobs->Add(Base64(positions))},
                         {"indices", blobs->Add(Base64(indices))}});
      }
    }
    arm["links"] = std::move(links);
    arm["stops"] = std::move(stops);
    page["arm"] = std::move(arm);
  }
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
  // The ceiling, each target part and the mounting tolerance (issue 46): report.json's own
  // entries, so that the page and the file cannot disagree.
  page["answers"] = ordered_json::parse(ReportAnswersJsonText(report));
  page["whatif"] = std::move(whatif);
  page["voxels"] = std::move(voxels);
  page["meshes"] = std::move(meshes_json);

  std::string subtitle =
      fmt::format("{} · {} reference voxels of {} m · {} candidates", detail::AsUtf8(report.scene),
                  reference_size,
                  data.reference.cell_size, data.candidates.size());
  if (primary >= 0) {
    const Selection& s = report.results[static_cast<size_t>(primary)];
    subtitle += fmt::format(" · {} N = {}: {:.2f} %", s.method, s.n, 100.0 * s.coverage);
    // Point density (docs/constraints.md): the coverages count only cells with enough points.
    if (s.min_points) subtitle += fmt::format(" of cells with >= {} points", *s.min_points);
  }
  const std::string title = "vantage report";

  const std::string escaped_title = detail::MarkupEscape(title);
  const std::string escaped_subtitle = detail::MarkupEscape(subtitle);
  const std::string json = page.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  // Written once into a string of about the page's size (issue 47: each copy of its megabytes
  // was page faults).
  std::string out;
  out.reserve(embedded::kReportHtml.size() + embedded::kReportCss.size() +
              embedded::kReportJs.size() + three.size() + orbit.size() + json.size() +
              blobs->bytes() + escaped_title.size() * 2 + escaped_subtitle.size() + 4096);
  bool fits = true;
  FillTemplate(embedded::kReportHtml,
               {{"TITLE", [&](std::string* o) { o->append(escaped_title); }},
                {"SUBTITLE", [&](std::string* o) { o->append(escaped_subtitle); }},
                {"STYLE", [&](std::string* o) { o->append(embedded::kReportCss); }},
                {"THREE",
                 [&](std::string* o) {
                   if (!has_three) return;
                   for (const std::string* text : {&three, &orbit}) {
                     o->append("<script>\n");
                     AppendScriptSafe(*text, o);
                     o->append("\n</script>\n");
                   }
                 }},
                {"DATA", [&](std::string* o) { fits = fits && blobs->AppendJson(json, o); }},
                {"SCRIPT", [&](std::string* o) { AppendScriptSafe(embedded::kReportJs, o); }}},
               &out);
  if (!fits) return std::nullopt;
  return out;
}

}  // namespace

std::string HtmlReport(const Report& report, const Scene& scene, const HtmlReportOptions& options) {
  Blobs blobs(false);
  if (std::optional<std::string> page = BuildPage(report, scene, options, &blobs))
    return std::move(*page);
  Blobs inline_blobs(true);
  std::optional<std::string> page = BuildPage(report, scene, options, &inline_blobs);
  VANTAGE_CHECK(page.has_value());
  return std::move(*page);
}

}  // namespace vantage
