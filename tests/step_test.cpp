// CAD in (issue 46): STEP and IGES read with OpenCASCADE. The fixtures are written by
// tests/step_fixtures.cpp from primitives at build time, in millimetres; the areas are checked
// against the analytic ones within what the chord deflection allows, the assembly's parts by
// name, place and colour, and broken files by their messages.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "scene/step_reader.hpp"
#include "test_util.hpp"
#include "vantage/error.hpp"
#include "vantage/pipeline.hpp"
#include "vantage/problem.hpp"

namespace vantage {
namespace {

using detail::CadPart;
using detail::ReadCadFile;

std::string Fixture(const std::string& name) { return std::string(VANTAGE_CAD_FIXTURES) + "/" + name; }

// A mesh whose vertices lie on a convex surface (BRepMesh puts its nodes on the surface) and
// whose chords are within `d` of it has an area between that of the surface shrunk by d and the
// surface's own: for a cylinder of radius r and height h, each cap is a polygon inscribed in the
// circle and holding the circle of radius r - d (its apothem), and the side's perimeter is at least
// 2π (r - d).
TEST(StepReader, BoxAreaIsExactInMetres) {
  for (const char* name : {"box.step", "box.igs"}) {
    const std::vector<CadPart> parts = ReadCadFile(Fixture(name), 0.001);
    ASSERT_EQ(parts.size(), 1u) << name;
    // 100 x 200 x 300 mm: planar faces are meshed exactly, whatever the deflection.
    EXPECT_NEAR(parts[0].mesh.Area(), 2 * (0.1 * 0.2 + 0.1 * 0.3 + 0.2 * 0.3), 1e-9) << name;
    const Aabb box = parts[0].mesh.Bounds();
    EXPECT_NEAR(box.max.x() - box.min.x(), 0.1, 1e-9) << name;
    EXPECT_NEAR(box.max.y() - box.min.y(), 0.2, 1e-9) << name;
    EXPECT_NEAR(box.max.z() - box.min.z(), 0.3, 1e-9) << name;
  }
  EXPECT_EQ(ReadCadFile(Fixture("box.step"), 0.001)[0].name, "box");
}

TEST(StepReader, CylinderAreaWithinTheDeflectionBound) {
  const double r = 0.05, h = 0.12;
  const auto area = [&](double radius) { return 2 * std::numbers::pi * radius * (radius + h); };
  for (const double d : {0.005, 0.001, 0.0002}) {
    const std::vector<CadPart> parts = ReadCadFile(Fixture("cylinder.step"), d);
    ASSERT_EQ(parts.size(), 1u);
    const double meshed = parts[0].mesh.Area();
    // Lower: caps π (r-d)², side 2π (r-d) h; upper: the true surface (the mesh is inscribed).
    EXPECT_GE(meshed, 2 * std::numbers::pi * (r - d) * (r - d) + 2 * std::numbers::pi * (r - d) * h)
        << "deflection " << d;
    EXPECT_LE(meshed, area(r) + 1e-12) << "deflection " << d;
  }
  // A finer deflection is closer: the bound is not met by luck.
  const double coarse = ReadCadFile(Fixture("cylinder.step"), 0.005)[0].mesh.Area();
  const double fine = ReadCadFile(Fixture("cylinder.step"), 0.0002)[0].mesh.Area();
  EXPECT_LT(area(r) - fine, area(r) - coarse);
}

TEST(StepReader, AssemblyPartsByProductNamePlacedAndColoured) {
  const std::vector<CadPart> parts = ReadCadFile(Fixture("cell.step"), 0.0005);
  std::vector<std::string> names;
  for (const CadPart& part : parts) names.push_back(part.name);
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"bolt", "bolt#2", "bracket", "plate"}));
  for (const CadPart& part : parts) {
    const Aabb box = part.mesh.Bounds();
    if (part.name == "bracket") {
      // A 40 x 40 x 10 mm box placed at (80, 30, 5) mm.
      EXPECT_NEAR(box.min.x(), 0.080, 1e-9);
      EXPECT_NEAR(box.min.y(), 0.030, 1e-9);
      EXPECT_NEAR(box.min.z(), 0.005, 1e-9);
      EXPECT_NEAR(box.max.z(), 0.015, 1e-9);
      EXPECT_NEAR(part.mesh.Area(), 2 * (0.04 * 0.04 + 2 * 0.04 * 0.01), 1e-9);
      ASSERT_TRUE(part.colour.has_value());
      EXPECT_NEAR((*part.colour)[0], 0, 1e-6);
      EXPECT_NEAR((*part.colour)[1], 1, 1e-6);
      EXPECT_NEAR((*part.colour)[2], 0, 1e-6);
    } else if (part.name == "plate") {
      EXPECT_NEAR(box.max.x(), 0.200, 1e-9);
      EXPECT_NEAR(box.max.z(), 0.005, 1e-9);
      ASSERT_TRUE(part.colour.has_value());
      EXPECT_GT((*part.colour)[0], 0.1);  // grey, not green
    } else {
      // The two bolts: radius 5 mm, 20 mm high, at (20, 20, 5) and (180, 80, 5) mm.
      EXPECT_NEAR(box.max.z() - box.min.z(), 0.020, 1e-9);
      const double cx = (box.min.x() + box.max.x()) / 2;
      EXPECT_TRUE(std::abs(cx - 0.020) < 1e-6 || std::abs(cx - 0.180) < 1e-6) << cx;
    }
  }
}

TEST(StepReader, BrokenAndUnsupportedFilesAreInputErrorsNamingThem) {
  test::TempDir dir;
  const auto refused = [&](const std::string& name, const std::string& text,
                           const std::string& needle) {
    const std::string path = dir.File(name);
    if (!text.empty()) test::WriteText(path, text);
    try {
      ReadCadFile(path, 0.001);
      ADD_FAILURE() << name << " was read";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind(path + ":", 0), 0u) << what;
      EXPECT_NE(what.find(needle), std::string::npos) << what;
    }
  };
  refused("missing.step", "", "missing");
  refused("empty.step", "\n", "OpenCASCADE");
  refused("words.stp", "this is no STEP file\n", "OpenCASCADE");
  // Half a STEP file: the header and no data section's end.
  const std::string box = test::ReadText(Fixture("box.step"));
  refused("cut.step", box.substr(0, box.size() / 3), "OpenCASCADE");
  // A file of no solid or face: the data section holds only a point.
  refused("point.step",
          "ISO-10303-21;\nHEADER;\nFILE_DESCRIPTION((''),'2;1');\nFILE_NAME('p','',(''),(''),'','','');\n"
          "FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));\nENDSEC;\nDATA;\n"
          "#1=CARTESIAN_POINT('',(0.,0.,0.));\nENDSEC;\nEND-ISO-10303-21;\n",
          "OpenCASCADE");
  refused("garbage.igs", "not IGES at all\n", "OpenCASCADE");
  std::filesystem::create_directories(dir.File("folder.step"));
  refused("folder.step", "", "folder");
}

// The scene readers: a YAML mesh naming a STEP assembly gives one object per solid, named
// OBJECT/PART, so that --target picks a part; role by_colour makes the green part the target.
TEST(StepReader, YamlAssemblyObjectsAndTargetsByColour) {
  test::TempDir dir;
  const std::string scene = dir.File("cell.yaml");
  test::WriteText(scene, fmt::format(R"(settings: {{cell_size: 0.004}}
objects:
  - name: fixture
    role: by_colour
    mesh: {{file: {}}}
    pose: {{xyz: [1, 0, 0]}}
sensors:
  - {{name: cam, type: intel_realsense_d435, position: [1.1, 0.05, 0.5]}}
)",
                                     Fixture("cell.step")));
  const Problem problem = LoadProblem(scene);
  std::vector<std::string> names, targets;
  for (const SceneObject& object : problem.scene.objects) {
    names.push_back(object.name);
    if (object.is_target()) targets.push_back(object.name);
  }
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"fixture/bolt", "fixture/bolt#2", "fixture/bracket",
                                             "fixture/plate"}));
  EXPECT_EQ(targets, (std::vector<std::string>{"fixture/bracket"}));
  for (const SceneObject& object : problem.scene.objects) {
    if (object.name == "fixture/bracket") {  // placed by the object's pose, in metres
      EXPECT_NEAR(object.mesh.Bounds().min.x(), 1.080, 1e-9);
    }
  }
  // --target picks a part by its name.
  LoadOptions options;
  options.targets = {"fixture/plate"};
  const Problem picked = LoadProblem(scene, options);
  for (const SceneObject& object : picked.scene.objects)
    EXPECT_EQ(object.is_target(), object.name == "fixture/plate") << object.name;
  // by_colour on a mesh that is no CAD file is refused at the object's line.
  test::WriteText(dir.File("plain.yaml"),
                  "objects:\n  - name: box\n    role: by_colour\n    box: {size: [1, 1, 1]}\n");
  try {
    LoadProblem(dir.File("plain.yaml"));
    ADD_FAILURE() << "by_colour without CAD was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.File("plain.yaml") + ":2:"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace vantage
