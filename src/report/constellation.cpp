#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <set>

#include "vantage/error.hpp"
#include "report/run_inputs.hpp"
#include "util/words.hpp"
#include "vantage/report.hpp"
#include "vantage/words.hpp"

namespace vantage {
namespace {

using nlohmann::json;

int LineOfByte(const std::string& text, size_t byte) {
  byte = std::min(byte, text.size());
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(byte), '\n'));
}

double Number(const json& object, const char* key, const std::string& where) {
  if (!object.contains(key) || !object[key].is_number())
    throw InputError(fmt::format("{}: '{}' must be a number", where, key));
  const double v = object[key].get<double>();
  if (!std::isfinite(v)) throw InputError(fmt::format("{}: '{}' must be finite", where, key));
  return v;
}

std::vector<double> Numbers(const json& object, const char* key, size_t count, const std::string& where) {
  if (!object.contains(key) || !object[key].is_array() || object[key].size() != count)
    throw InputError(fmt::format("{}: '{}' must be an array of {} numbers", where, key, count));
  std::vector<double> out;
  for (const json& v : object[key]) {
    if (!v.is_number() || !std::isfinite(v.get<double>()))
      throw InputError(fmt::format("{}: '{}' must hold finite numbers", where, key));
    out.push_back(v.get<double>());
  }
  return out;
}

Candidate ParseCandidate(const json& j, const std::string& where) {
  if (!j.is_object()) throw InputError(fmt::format("{}: must be an object", where));
  Candidate c;
  if (!j.contains("name") || !j["name"].is_string() || j["name"].get<std::string>().empty())
    throw InputError(fmt::format("{}: 'name' must be a non-empty string", where));
  c.name = j["name"].get<std::string>();
  c.type_id = j.contains("type") && j["type"].is_string() ? j["type"].get<std::string>() : "custom";
  // The scene readers' check (util/words.hpp): a name with a newline breaks candidates.csv and
  // the exported XML (issue 15).
  for (const auto& [field, text] : {std::pair<const char*, const std::string*>{"name", &c.name},
                                    {"type", &c.type_id}}) {
    if (const std::string problem = detail::NameProblem(*text); !problem.empty())
      throw InputError(
          fmt::format("{}: {} '{}' {}", where, field, detail::Escaped(*text), problem));
  }
  const std::string at = fmt::format("{} ('{}')", where, c.name);
  const std::vector<double> p = Numbers(j, "position", 3, at);
  const std::vector<double> q = Numbers(j, "quaternion", 4, at);
  const std::optional<Quat> rotation = QuatFromWxyz(q);
  if (!rotation) throw InputError(fmt::format("{}: 'quaternion' is zero, or shorter than 1e-09 (no "
                                                  "direction to normalise)", at));
  c.world_from_body = Pose{Vec3(p[0], p[1], p[2]), *rotation};
  SensorType& s = c.sensor;
  s.id = c.type_id;
  s.name = c.type_id;
  const double width = Number(j, "width", at), height = Number(j, "height", at);
  if (width < 1 || height < 1 || width != std::floor(width) || height != std::floor(height) ||
      width > 1e5 || height > 1e5)
    throw InputError(fmt::format("{}: width and height must be whole numbers >= 1", at));
  s.width = static_cast<int>(width);
  s.height = static_cast<int>(height);
  s.fx = Number(j, "fx", at);
  s.fy = Number(j, "fy", at);
  s.cx = Number(j, "cx", at);
  s.cy = Number(j, "cy", at);
  s.near = Number(j, "near", at);
  s.far = Number(j, "far", at);
  if (const SensorType* catalog = FindCatalogType(c.type_id)) {
    s.name = catalog->name;
    s.technology = catalog->technology;
    s.fps = catalog->fps;
    s.cost = catalog->cost;
  }
  CheckCandidate(c, at);  // the type (SensorType::Validate) and the position
  return c;
}

}  // namespace

Constellation LoadConstellation(const std::string& path) {
  // A device or a pipe is refused before it is read (issue 15: /dev/zero ran out of memory, a
  // FIFO blocked forever).
  const std::string text = detail::ReadInputFile(path, "constellation file");
  json j;
  try {
    j = json::parse(text);
  } catch (const json::parse_error& e) {
    // nlohmann quotes the bytes it last read, raw: shown as UTF-8 with controls escaped.
    throw InputError(AtPlace(path, LineOfByte(text, e.byte > 0 ? e.byte - 1 : 0),
                             fmt::format("not valid JSON ({}) — give a report.json written by vantage",
                                         ShownOnOneLine(e.what()))));
  } catch (const json::exception& e) {  // e.g. a number out of range: no byte position
    throw InputError(AtPlace(path, 0, fmt::format("not valid JSON ({}) — give a report.json written "
                                                  "by vantage",
                                                  ShownOnOneLine(e.what()))));
  }
  if (!j.is_object() || !j.contains("candidates") || !j["candidates"].is_array())
    throw InputError(AtPlace(path, 1, "no 'candidates' array — give a report.json written by vantage"));
  if (j.contains("schema") && j["schema"] != "vantage.report/1")
    throw InputError(AtPlace(path, 1, fmt::format("schema {} is not vantage.report/1", j["schema"].dump())));
  std::vector<Candidate> all;
  std::set<std::string> names;
  for (size_t i = 0; i < j["candidates"].size(); ++i) {
    Candidate c = ParseCandidate(j["candidates"][i], AtPlace(path, 0, fmt::format("candidates[{}]", i)));
    if (!names.insert(c.name).second)
      throw InputError(AtPlace(path, 0, fmt::format("candidates[{}]: duplicate name '{}'", i, c.name)));
    all.push_back(std::move(c));
  }
  Constellation constellation;
  if (j.contains("results") && !j["results"].is_null() && !j["results"].is_array())
    throw InputError(AtPlace(path, 0, "'results' must be an array of results — give a report.json "
                                      "written by vantage"));
  const bool has_selection = j.contains("results") && j["results"].is_array() && !j["results"].empty();
  if (!has_selection && j.contains("primary_result") && !j["primary_result"].is_null())
    throw InputError(AtPlace(path, 0, fmt::format("primary_result {} names no result: there are "
                                                  "none — drop it to evaluate every candidate",
                                                  j["primary_result"].dump())));
  if (!has_selection) {
    constellation.sensors = std::move(all);
  } else {
    // The primary result when the report names one, else the first entry.
    size_t which = 0;
    if (j.contains("primary_result") && !j["primary_result"].is_null()) {
      // An index that names no result is an error, not result 0 (issue 15).
      const json& primary = j["primary_result"];
      if (!primary.is_number_unsigned() || primary.get<size_t>() >= j["results"].size())
        throw InputError(AtPlace(
            path, 0,
            fmt::format("primary_result {} names no result — give an index from 0 to {} (there "
                        "are {} results)",
                        primary.dump(), j["results"].size() - 1, j["results"].size())));
      which = primary.get<size_t>();
    }
    const json& result = j["results"][which];
    if (result.is_object() && result.contains("coverage") && result["coverage"].is_number())
      constellation.coverage = result["coverage"].get<double>();
    if (!result.is_object() || !result.contains("sensors") || !result["sensors"].is_array())
      throw InputError(AtPlace(path, 0, fmt::format("results[{}]: 'sensors' must be an array of names", which)));
    std::set<std::string> chosen;
    for (const json& name : result["sensors"]) {
      if (!name.is_string()) throw InputError(AtPlace(path, 0, "results: sensor names must be strings"));
      // One sensor named twice would be scored as two (issue 15).
      if (!chosen.insert(name.get<std::string>()).second)
        throw InputError(AtPlace(path, 0, fmt::format("results[{}] names sensor '{}' twice — list "
                                                      "each chosen sensor once",
                                                      which, name.get<std::string>())));
      const auto it = std::find_if(all.begin(), all.end(),
                                   [&](const Candidate& c) { return c.name == name.get<std::string>(); });
      if (it == all.end())
        throw InputError(AtPlace(path, 0, fmt::format("results[{}] names sensor '{}', which is not among "
                                                      "the candidates", which, name.get<std::string>())));
      constellation.sensors.push_back(*it);
    }
  }
  if (constellation.sensors.empty())
    throw InputError(AtPlace(path, 0, "the constellation holds no sensor"));
  if (j.contains("scene") && j["scene"].is_string()) constellation.scene = j["scene"].get<std::string>();
  if (j.contains("cell_size") && j["cell_size"].is_number())
    constellation.cell_size = j["cell_size"].get<double>();
  if (j.contains("inputs")) constellation.inputs = detail::ParseRunInputs(j["inputs"], path);
  return constellation;
}

}  // namespace vantage
