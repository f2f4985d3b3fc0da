// Where files come from: the model path (--model-path, GAZEBO_MODEL_PATH, the world's models/
// folder) and the resource path, model:// and file:// URIs, model.config, loading each SDF file
// once, and <include> resolution with Gazebo classic's stand-ins for models that are not on the
// path (ground_plane, sun). GAZEBO.md, "Files and paths".
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "scene/sdf/loader.hpp"
#include "scene/sdf/text.hpp"
#include "vantage/words.hpp"

namespace vantage::detail::gazebo {
namespace {

namespace fs = std::filesystem;

/// Models that hold only a light when they are not on the path (Gazebo's database `sun`).
bool IsLightModelName(const std::string& name) { return name == "sun"; }

/// The model name in a URI: "model://sun" -> "sun", "file:///a/b/box/" -> "box".
std::string UriBaseName(const std::string& uri) {
  std::string rest = uri;
  const size_t scheme = rest.find("://");
  if (scheme != std::string::npos) rest = rest.substr(scheme + 3);
  while (!rest.empty() && rest.back() == '/') rest.pop_back();
  if (uri.rfind("model://", 0) == 0) return rest.substr(0, rest.find('/'));
  const size_t slash = rest.rfind('/');
  return slash == std::string::npos ? rest : rest.substr(slash + 1);
}

/// %XX escapes decoded ("Coke%20Can" -> "Coke Can"); a malformed escape stays as written.
std::string PercentDecoded(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '%' && i + 2 < text.size() && std::isxdigit(static_cast<unsigned char>(text[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(text[i + 2]))) {
      out.push_back(static_cast<char>(std::stoi(text.substr(i + 1, 2), nullptr, 16)));
      i += 2;
    } else {
      out.push_back(text[i]);
    }
  }
  return out;
}

/// The entry of `dir` named `name`, compared without case (Fuel's owners and names are
/// case-insensitive; the cache keeps the owner in lower case); "" when there is none.
std::string EntryNoCase(const std::string& dir, const std::string& name) {
  if (IsDirectory((fs::path(dir) / name).string())) return (fs::path(dir) / name).string();
  std::error_code ec;
  std::vector<std::string> matches;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    if (LowerCase(entry.path().filename().string()) == LowerCase(name)) matches.push_back(entry.path());
  }
  std::sort(matches.begin(), matches.end());  // directory order is not stable
  return matches.empty() ? "" : matches.front();
}

// The elements vantage reads as one value, by parent: SDF allows each once there (libsdformat,
// like vantage, reads the first), so a second one is an edit that silently does nothing. <pose>
// is single in every element vantage reads.
const std::vector<std::pair<std::string_view, std::vector<std::string_view>>>& SingleChildren() {
  static const std::vector<std::pair<std::string_view, std::vector<std::string_view>>> table = {
      {"model", {"static"}},
      {"include", {"uri", "name", "static"}},
      {"visual", {"geometry", "material", "transparency"}},
      {"box", {"size"}},
      {"cylinder", {"radius", "length"}},
      {"capsule", {"radius", "length"}},
      {"sphere", {"radius"}},
      {"ellipsoid", {"radii"}},
      {"plane", {"normal", "size"}},
      {"mesh", {"uri", "scale", "submesh"}},
      {"material", {"script", "diffuse", "ambient"}},
      {"script", {"name"}},
      {"sensor", {"update_rate", "always_on", "visualize"}},
      {"camera", {"horizontal_fov", "image", "clip"}},
      {"image", {"width", "height", "format"}},
      {"clip", {"near", "far"}},
      {"population", {"model", "model_count", "distribution", "box", "cylinder"}},
      {"distribution", {"type", "rows", "cols", "step"}},
  };
  return table;
}

// The shapes of <geometry>: libsdformat picks one by its own order (box before sphere), vantage
// the first written, so two of them are ambiguous, not only redundant.
bool IsShape(std::string_view name) {
  static constexpr std::string_view kShapes[] = {"box",       "capsule", "cylinder", "ellipsoid",
                                                 "heightmap", "image",   "mesh",     "plane",
                                                 "polyline",  "sphere",  "empty"};
  return std::find(std::begin(kShapes), std::end(kShapes), name) != std::end(kShapes);
}

struct Repeat {
  const XmlElement* parent;
  const XmlElement* first;
  const XmlElement* second;
};

// Every second occurrence of a single element below `element` (plugins, whose content is their
// own, and namespaced extensions are skipped), and every second shape of a <geometry>.
void FindRepeats(const XmlElement& element, std::vector<Repeat>* repeats,
                 std::vector<Repeat>* shapes) {
  if (element.name == "plugin" || element.name.find(':') != std::string::npos) return;
  const auto& table = SingleChildren();
  const auto row = std::find_if(table.begin(), table.end(),
                                [&](const auto& entry) { return entry.first == element.name; });
  const XmlElement* shape = nullptr;
  for (size_t i = 0; i < element.children.size(); ++i) {
    const XmlElement& child = element.children[i];
    if (element.name == "geometry" && IsShape(child.name)) {
      // Several <polyline> make one shape (SDF 1.9); a shape beside another is the conflict.
      if (shape && !(shape->name == "polyline" && child.name == "polyline"))
        shapes->push_back({&element, shape, &child});
      if (!shape) shape = &child;
      continue;
    }
    const bool single =
        child.name == "pose" ||
        (row != table.end() &&
         std::find(row->second.begin(), row->second.end(), child.name) != row->second.end());
    if (!single) continue;
    for (size_t j = 0; j < i; ++j) {
      if (element.children[j].name == child.name) {
        repeats->push_back({&element, &element.children[j], &child});
        break;
      }
    }
  }
  for (const XmlElement& child : element.children) FindRepeats(child, repeats, shapes);
}

}  // namespace

std::optional<FuelUri> ParseFuelUri(const std::string& uri) {
  // https://fuel.gazebosim.org/1.0/<owner>/models/<name>[/<version>][/files/<path>]
  const size_t scheme = uri.find("://");
  if (scheme == std::string::npos) return std::nullopt;
  const std::string protocol = LowerCase(uri.substr(0, scheme));
  if (protocol != "https" && protocol != "http") return std::nullopt;
  std::vector<std::string> parts = SplitList(uri.substr(scheme + 3), '/');
  parts.erase(std::remove(parts.begin(), parts.end(), std::string()), parts.end());
  if (parts.size() < 5 || LowerCase(parts[3]) != "models") return std::nullopt;
  FuelUri fuel;
  fuel.host = LowerCase(parts[0]);
  fuel.owner = PercentDecoded(parts[2]);
  fuel.name = PercentDecoded(parts[4]);
  size_t next = 5;
  if (next < parts.size() && LowerCase(parts[next]) != "files") fuel.version = parts[next++];
  if (next < parts.size() && LowerCase(parts[next]) == "files") {
    std::vector<std::string> rest(parts.begin() + static_cast<std::ptrdiff_t>(next + 1), parts.end());
    fuel.file = PercentDecoded(Join(rest, "/"));
  } else if (next < parts.size()) {
    return std::nullopt;
  }
  return fuel;
}

Loader::Loader(std::string path, const LoadOptions& options)
    : path_(std::move(path)), options_(options) {
  for (const std::string& dir : options_.model_paths) model_dirs_.push_back(dir);
  // gz-sim's resource path (and its Ignition-era name) holds model folders too, and comes first.
  for (const char* variable : {"GZ_SIM_RESOURCE_PATH", "IGN_GAZEBO_RESOURCE_PATH"})
    for (const std::string& dir : PathListFromEnv(variable)) model_dirs_.push_back(dir);
  for (const std::string& dir : PathListFromEnv("GAZEBO_MODEL_PATH")) model_dirs_.push_back(dir);
  // The local Fuel cache (gz-fuel-tools' layout: <cache>/<host>/<owner>/models/<name>/<version>).
  if (const std::vector<std::string> cache = PathListFromEnv("GZ_FUEL_CACHE_PATH"); !cache.empty()) {
    fuel_cache_dirs_ = cache;
  } else if (const std::vector<std::string> home = PathListFromEnv("HOME"); !home.empty()) {
    fuel_cache_dirs_ = {(fs::path(home.front()) / ".gz" / "fuel").string(),
                        (fs::path(home.front()) / ".ignition" / "fuel").string()};
  }
  model_dirs_.push_back((fs::path(path_).parent_path() / "models").lexically_normal().string());
  for (const std::string& dir : options_.resource_paths) resource_dirs_.push_back(dir);
  for (const char* variable : {"GAZEBO_RESOURCE_PATH", "GZ_SIM_RESOURCE_PATH",
                               "IGN_GAZEBO_RESOURCE_PATH"})
    for (const std::string& dir : PathListFromEnv(variable)) resource_dirs_.push_back(dir);
  for (const std::string& dir : model_dirs_) resource_dirs_.push_back(ParentDir(dir + "/"));
}

const Doc* Loader::LoadSdf(const std::string& path, const std::string& model_dir) {
  // One document per file, however it is spelled (model://ts and file:///abs/ts): else a model
  // including itself by another spelling was walked once more before the cycle was seen, and
  // named with the nested 'ts::ts' (session 9).
  std::error_code ec;
  const fs::path canonical = fs::weakly_canonical(path, ec);
  const std::string key = ec ? fs::path(path).lexically_normal().string() : canonical.string();
  const auto it = docs_.find(key);
  if (it != docs_.end()) return it->second.get();
  std::unique_ptr<Doc> doc;
  try {
    doc = std::make_unique<Doc>();
    doc->xml = ReadXmlFile(path);
    doc->dir = ParentDir(path);
    doc->model_dir = model_dir;
  } catch (const InputError& e) {
    AddError(e.what());
    doc.reset();
  }
  if (doc) {
    const XmlElement& root = doc->xml.root;
    const std::string* version = root.Attribute("version");
    const auto parsed = version ? ParseVersion(Trim(*version)) : std::nullopt;
    if (root.name != "sdf") {
      Error(*doc, root.line,
            fmt::format("root element is <{}> — an SDF file starts with "
                        "<sdf version=\"1.6\">",
                        root.name));
      doc.reset();
    } else if (!parsed || parsed->first != 1) {
      Error(*doc, root.line,
            fmt::format("<sdf> needs a version attribute 1.N (got '{}'): vantage reads "
                        "SDF 1.4 to 1.11, and other 1.N as those with a note — write "
                        "<sdf version=\"1.6\">",
                        version ? *version : ""));
      doc.reset();
    } else if (const int minor = parsed.value_or(std::make_pair(0, 0)).second;
               minor < 4 || minor > 11) {  // parsed is set; value_or spares a false GCC warning
      Note(AtPlace(path, root.line,
                   fmt::format("SDF version {} is read as 1.4–1.11 (vantage "
                               "implements those)",
                               *version)));
    }
  }
  if (doc) {
    std::vector<Repeat> repeats, shapes;
    FindRepeats(doc->xml.root, &repeats, &shapes);
    for (const Repeat& r : repeats)
      Warn(AtPlace(path, r.second->line,
                   fmt::format("a second <{}> in <{}> (the first at line {}) is not read — "
                               "vantage, like Gazebo, reads the first; remove one",
                               r.second->name, r.parent->name, r.first->line)));
    for (const Repeat& r : shapes)
      Error(*doc, r.second->line,
            fmt::format("<geometry> has <{}> (line {}) and <{}>: one shape per geometry — Gazebo "
                        "and vantage would not pick the same; keep one, or give each its own "
                        "<visual>",
                        r.first->name, r.first->line, r.second->name));
  }
  const Doc* result = doc.get();
  docs_[key] = std::move(doc);
  return result;
}

std::string Loader::ModelFileInDir(const std::string& dir, const Doc& from, int line) {
  const std::string config_path = (fs::path(dir) / "model.config").string();
  std::string chosen;
  if (IsFile(config_path)) {
    try {
      const XmlDocument config = ReadXmlFile(config_path);
      std::pair<int, int> best{-1, -1};
      for (const XmlElement* sdf : config.root.Children("sdf")) {
        const std::string* version = sdf->Attribute("version");
        const auto parsed = version ? ParseVersion(Trim(*version)) : std::nullopt;
        const std::pair<int, int> v = parsed.value_or(std::make_pair(0, 0));
        if (!sdf->Trimmed().empty() && v > best) {
          best = v;
          chosen = (fs::path(dir) / sdf->Trimmed()).string();
        }
      }
      if (!chosen.empty() && !IsFile(chosen)) {
        Error(config_path, config.root.line,
              fmt::format("model.config names '{}', which does not exist — fix its <sdf> element",
                          chosen));
        return "";
      }
    } catch (const InputError& e) {
      AddError(e.what());
      return "";
    }
  }
  if (chosen.empty()) chosen = (fs::path(dir) / "model.sdf").string();
  if (!IsFile(chosen)) {
    Error(from, line,
          fmt::format("model folder '{}' has no model.sdf and no model.config naming "
                      "its SDF file",
                      dir));
    return "";
  }
  return chosen;
}

std::optional<std::string> Loader::ResolveModelUri(const std::string& uri,
                                                   const Doc& from,
                                                   std::vector<std::string>* searched) {
  std::string rest;
  if (uri.rfind("model://", 0) == 0) {
    rest = uri.substr(8);
    const size_t slash = rest.find('/');
    const std::string name = rest.substr(0, slash);
    const std::string sub = slash == std::string::npos ? "" : rest.substr(slash + 1);
    if (name.empty()) return std::nullopt;
    // A URI's percent-escapes are decoded once ("My%20Part" is the folder "My Part"); the text
    // as written is tried after, for a folder whose name holds a literal '%'.
    std::vector<std::pair<std::string, std::string>> spellings = {
        {PercentDecoded(name), PercentDecoded(sub)}};
    if (spellings.front() != std::make_pair(name, sub)) spellings.emplace_back(name, sub);
    if (searched) AppendOnce(model_dirs_, searched);  // each folder once, however often given
    for (const auto& [folder, file] : spellings) {
      for (const std::string& dir : model_dirs_) {
        const fs::path model_dir = fs::path(dir) / folder;
        if (!IsDirectory(model_dir.string())) continue;
        const fs::path candidate = file.empty() ? model_dir : model_dir / file;
        std::error_code ec;
        if (fs::exists(candidate, ec)) return candidate.lexically_normal().string();
      }
    }
    return std::nullopt;
  }
  if (const std::optional<FuelUri> fuel = ParseFuelUri(uri)) return FuelCached(*fuel, searched);
  if (uri.find("://") != std::string::npos && uri.rfind("file://", 0) != 0) return std::nullopt;
  rest = uri.rfind("file://", 0) == 0 ? uri.substr(7) : uri;
  if (rest.empty()) return std::nullopt;
  std::vector<std::string> bases;
  if (fs::path(rest).is_absolute()) {
    bases.emplace_back();
  } else {
    bases.push_back(from.dir);
    if (!from.model_dir.empty()) bases.push_back(from.model_dir);
    bases.push_back(ParentDir(path_));
  }
  for (const std::string& base : bases) {
    const fs::path candidate = base.empty() ? fs::path(rest) : fs::path(base) / rest;
    if (searched) AppendOnce({candidate.parent_path().string()}, searched);
    std::error_code ec;
    if (fs::exists(candidate, ec)) return candidate.lexically_normal().string();
  }
  return std::nullopt;
}

std::optional<std::string> Loader::FuelCached(const FuelUri& fuel,
                                              std::vector<std::string>* searched) {
  for (const std::string& cache : fuel_cache_dirs_) {
    const fs::path models = fs::path(cache) / fuel.host;
    if (searched) searched->push_back(models.string());
    const std::string owner = EntryNoCase(models.string(), fuel.owner);
    if (owner.empty()) continue;
    const std::string model = EntryNoCase((fs::path(owner) / "models").string(), fuel.name);
    if (model.empty()) continue;
    std::string version;
    if (!fuel.version.empty() && LowerCase(fuel.version) != "tip") {
      version = (fs::path(model) / fuel.version).string();
      if (!IsDirectory(version)) continue;
    } else {
      // "tip" or none: the newest version in the cache (versions are whole numbers).
      int newest = -1;
      std::error_code ec;
      for (const auto& entry : fs::directory_iterator(model, ec)) {
        const auto number = ParseInteger(entry.path().filename().string());
        if (number && entry.is_directory(ec) && *number > newest) {
          newest = static_cast<int>(*number);
          version = entry.path().string();
        }
      }
      if (newest < 0) continue;
    }
    const fs::path found = fuel.file.empty() ? fs::path(version) : fs::path(version) / fuel.file;
    std::error_code ec;
    if (fs::exists(found, ec)) return found.lexically_normal().string();
  }
  return std::nullopt;
}

std::optional<std::string> Loader::ResolveResourceUri(const std::string& uri, const Doc& from,
                                                      std::vector<std::string>* searched) {
  if (uri.rfind("model://", 0) == 0 || ParseFuelUri(uri)) {
    std::vector<std::string> looked;
    const std::optional<std::string> found = ResolveModelUri(uri, from, &looked);
    if (searched) AppendOnce(looked, searched);
    return found;
  }
  if (uri.find("://") != std::string::npos && uri.rfind("file://", 0) != 0) return std::nullopt;
  const std::string rest = uri.rfind("file://", 0) == 0 ? uri.substr(7) : uri;
  if (rest.empty()) return std::nullopt;
  std::error_code ec;
  if (fs::path(rest).is_absolute()) {
    if (searched) AppendOnce({fs::path(rest).parent_path().string()}, searched);
    return fs::exists(rest, ec) ? std::optional<std::string>(rest) : std::nullopt;
  }
  // GAZEBO.md: --resource-path, GAZEBO_RESOURCE_PATH, the parent of each model directory; then
  // the file's own model folder and folder.
  std::vector<std::string> bases = resource_dirs_;
  if (!from.model_dir.empty()) bases.push_back(from.model_dir);
  bases.push_back(from.dir);
  if (searched) AppendOnce(bases, searched);
  for (const std::string& base : bases) {
    const fs::path candidate = fs::path(base) / rest;
    if (fs::exists(candidate, ec)) return candidate.lexically_normal().string();
  }
  return std::nullopt;
}

IncludeResult Loader::ResolveInclude(const Doc& doc, const XmlElement& include) {
  IncludeResult result;
  const XmlElement* uri_element = include.Child("uri");
  std::string uri = uri_element ? uri_element->Trimmed() : "";
  if (uri.empty()) {
    Error(doc, include.line, "<include> has no <uri> — add <uri>model://NAME</uri>");
    return result;
  }
  while (uri.size() > 1 && uri.back() == '/') uri.pop_back();
  const int line = uri_element->line;
  const XmlElement* name_element = include.Child("name");
  const std::string base = UriBaseName(uri);
  if (include.Attribute("merge") && BoolWord(*include.Attribute("merge")).value_or(false)) {
    Note(AtPlace(doc.xml.path, include.line,
                 fmt::format("<include merge='true'> of {}: read as a nested model", uri)));
  }
  std::vector<std::string> searched;
  const std::optional<std::string> location = ResolveModelUri(uri, doc, &searched);
  if (!location) {
    if (IsLightModelName(base)) {
      Note(
          AtPlace(doc.xml.path, line,
                  fmt::format("{} is not on the model path: skipped (a light, no geometry)", uri)));
      result.kind = IncludeResult::Kind::kSkipped;
      return result;
    }
    if (base == "ground_plane") {
      Note(AtPlace(doc.xml.path, line,
                   fmt::format("{} is not on the model path: read as Gazebo's ground plane, a "
                               "{} m x {} m plane at z = 0",
                               uri, kGroundPlaneSize, kGroundPlaneSize)));
      result.kind = IncludeResult::Kind::kGroundPlane;
      result.name = name_element ? name_element->Trimmed() : "ground_plane";
      return result;
    }
    if (ParseFuelUri(uri)) {
      Error(doc, line,
            fmt::format("<include> Fuel model '{}' is not in the local Fuel cache (looked in {}) "
                        "— vantage works offline: download it with `gz fuel download -u {}`, or "
                        "set GZ_FUEL_CACHE_PATH to the cache folder",
                        uri, searched.empty() ? "no cache folder: HOME is not set" : Join(searched, ", "),
                        uri));
      return result;
    }
    std::string where;
    if (uri.rfind("model://", 0) == 0) {
      where = searched.empty() ? "no model path is set" : "looked in " + Join(searched, ", ");
    } else if (uri.find("://") != std::string::npos && uri.rfind("file://", 0) != 0) {
      where = "vantage reads models from disk only";
    } else {
      where = "looked in " + Join(searched, ", ");
    }
    Error(doc, line,
          fmt::format("<include> model '{}' not found ({}) — add its folder's parent with "
                      "--model-path or GAZEBO_MODEL_PATH",
                      uri, where));
    return result;
  }
  std::string file = *location;
  std::string model_dir = ParentDir(file);
  if (IsDirectory(file)) {
    model_dir = file;
    file = ModelFileInDir(file, doc, line);
    if (file.empty()) return result;
  }
  const Doc* model_doc = LoadSdf(file, model_dir);
  if (!model_doc) return result;
  const std::vector<const XmlElement*> models = model_doc->xml.root.Children("model");
  if (models.empty()) {
    if (!model_doc->xml.root.Children("light").empty()) {
      Note(AtPlace(doc.xml.path, line, fmt::format("{} holds only a light: skipped", uri)));
      result.kind = IncludeResult::Kind::kSkipped;
      return result;
    }
    if (!model_doc->xml.root.Children("actor").empty()) {
      Note(AtPlace(doc.xml.path, line,
                   fmt::format("{} is an actor: skipped (vantage reads static scenes)", uri)));
      result.kind = IncludeResult::Kind::kSkipped;
      return result;
    }
    Error(*model_doc, model_doc->xml.root.line,
          fmt::format("no <model> element (included from {}:{}) — an included file holds one "
                      "<model>",
                      doc.xml.path, line));
    return result;
  }
  if (models.size() > 1) {
    Error(*model_doc, models[1]->line,
          fmt::format("{} <model> elements (included from {}:{}) — an included file holds one",
                      models.size(), doc.xml.path, line));
  }
  const std::string* own_name = models[0]->Attribute("name");
  result.name = name_element ? name_element->Trimmed() : own_name ? Trim(*own_name) : base;
  if (result.name.empty()) {
    Error(*model_doc, models[0]->line, "<model> has no name attribute — add name=\"...\"");
    return result;
  }
  result.kind = IncludeResult::Kind::kModel;
  result.doc = model_doc;
  result.model = models[0];
  return result;
}

}  // namespace vantage::detail::gazebo
