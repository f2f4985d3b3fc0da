// The CAD reader module (issue 47): STEP and IGES through OpenCASCADE's XCAF readers (names,
// colours, assemblies), each solid meshed by BRepMesh. The only file that includes OpenCASCADE;
// built as a shared module of its own (libvantage_cad.so) that step_reader.cpp loads with dlopen
// in the child process reading a CAD file, so that a run reading none never loads OpenCASCADE's
// 26 shared libraries (about 0.1 s of every process start). It uses no vantage library: only
// the CadPart layout (step_reader.hpp) and the bytes step_reader.cpp decodes.
#include "scene/step_reader.hpp"

#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESCAFControl_Reader.hxx>
#include <Interface_Check.hxx>
#include <Interface_CheckIterator.hxx>
#include <Interface_InterfaceModel.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Poly_Triangulation.hxx>
#include <Quantity_Color.hxx>
#include <STEPCAFControl_Reader.hxx>
#include <Standard_Failure.hxx>
#include <TCollection_AsciiString.hxx>
#include <TCollection_ExtendedString.hxx>
#include <TDF_Label.hxx>
#include <TDF_LabelSequence.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopExp_Explorer.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Shape.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_ColorTool.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <XSControl_WorkSession.hxx>
#include <XSControl_Reader.hxx>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <map>
#include <stdexcept>

namespace vantage::detail {
namespace {

// A file OpenCASCADE cannot read: the message goes back to the caller, which throws InputError.
struct CadFailure : std::runtime_error {
  using std::runtime_error::runtime_error;
};

[[noreturn]] void Fail(const std::string& path, const std::string& what) {
  throw CadFailure(fmt::format("{}: {}", path, what));
}

// The first failure OpenCASCADE's reader recorded, with the entity it is about ("#12" in STEP).
std::string FirstFailure(XSControl_Reader& reader) {
  const Handle(XSControl_WorkSession) session = reader.WS();
  if (session.IsNull()) return {};
  const Handle(Interface_InterfaceModel) model = session->Model();
  Interface_CheckIterator checks = session->ModelCheckList();
  for (checks.Start(); checks.More(); checks.Next()) {
    const Handle(Interface_Check)& check = checks.Value();
    if (check.IsNull() || !check->HasFailed()) continue;
    std::string entity;
    if (!model.IsNull() && check->HasEntity()) {
      const Handle(TCollection_HAsciiString) label = model->StringLabel(check->Entity());
      if (!label.IsNull()) entity = label->ToCString();
    } else if (checks.Number() > 0) {
      entity = fmt::format("#{}", checks.Number());
    }
    const std::string message = check->CFail(1) ? check->CFail(1) : "failed";
    return entity.empty() ? message : fmt::format("entity {}: {}", entity, message);
  }
  return {};
}

std::string NameOf(const TDF_Label& label) {
  Handle(TDataStd_Name) name;
  if (!label.FindAttribute(TDataStd_Name::GetID(), name)) return {};
  TCollection_AsciiString text(name->Get(), '?');  // non-ASCII letters become '?'
  std::string result = text.ToCString();
  // Names reach file:line messages and exports: no control characters.
  result.erase(std::remove_if(result.begin(), result.end(),
                              [](unsigned char c) { return c < 0x20 || c == 0x7f; }),
               result.end());
  return result;
}

std::optional<std::array<double, 3>> ColourOf(const Handle(XCAFDoc_ColorTool)& colours,
                                              const TDF_Label& label, const TopoDS_Shape& shape) {
  Quantity_Color colour;
  for (const XCAFDoc_ColorType type : {XCAFDoc_ColorSurf, XCAFDoc_ColorGen}) {
    if (colours->GetColor(label, type, colour) || colours->GetColor(shape, type, colour))
      return std::array<double, 3>{colour.Red(), colour.Green(), colour.Blue()};
  }
  return std::nullopt;
}

// The triangles of `shape`'s faces (meshed already), in metres and in the frame of its location.
TriangleMesh Triangles(const TopoDS_Shape& shape) {
  TriangleMesh mesh;
  for (TopExp_Explorer faces(shape, TopAbs_FACE); faces.More(); faces.Next()) {
    const TopoDS_Face& face = TopoDS::Face(faces.Current());
    TopLoc_Location location;
    const Handle(Poly_Triangulation) triangulation = BRep_Tool::Triangulation(face, location);
    if (triangulation.IsNull()) continue;
    const gp_Trsf transform = location.Transformation();
    const uint32_t first = static_cast<uint32_t>(mesh.vertices.size());
    for (int i = 1; i <= triangulation->NbNodes(); ++i) {
      const gp_Pnt p = triangulation->Node(i).Transformed(transform);
      mesh.vertices.emplace_back(p.X(), p.Y(), p.Z());
    }
    const bool reversed = face.Orientation() == TopAbs_REVERSED;
    for (int i = 1; i <= triangulation->NbTriangles(); ++i) {
      int a = 0, b = 0, c = 0;
      triangulation->Triangle(i).Get(a, b, c);
      if (reversed) std::swap(b, c);  // outward normals, as the other readers give
      mesh.triangles.push_back({first + static_cast<uint32_t>(a - 1),
                                first + static_cast<uint32_t>(b - 1),
                                first + static_cast<uint32_t>(c - 1)});
    }
  }
  return mesh;
}

struct Reader {
  Handle(XCAFDoc_ShapeTool) shapes;
  Handle(XCAFDoc_ColorTool) colours;
  double deflection = 0;
  std::vector<CadPart> parts;
  std::map<std::string, int> uses;  // by name: parts so named so far

  // A unique name: the product's, "#2"... after the first of that name.
  std::string Unique(std::string name) {
    if (name.empty()) name = fmt::format("solid_{}", parts.size() + 1);
    const int count = ++uses[name];
    return count == 1 ? name : fmt::format("{}#{}", name, count);
  }

  void AddShape(const TopoDS_Shape& shape, const std::string& name,
                const std::optional<std::array<double, 3>>& colour) {
    std::vector<TopoDS_Shape> solids;
    for (TopExp_Explorer it(shape, TopAbs_SOLID); it.More(); it.Next()) solids.push_back(it.Current());
    if (solids.empty()) solids.push_back(shape);  // a shell or faces: one part
    for (const TopoDS_Shape& solid : solids) {
      // Relative deflection off: the bound is absolute, in the document's unit (metres).
      BRepMesh_IncrementalMesh mesher(solid, deflection, Standard_False, 0.5, Standard_False);
      CadPart part;
      part.mesh = Triangles(solid);
      if (part.mesh.triangles.empty()) continue;
      part.name = Unique(name);
      part.colour = colour;
      parts.push_back(std::move(part));
    }
  }

  // A label of the document: an assembly's components in turn (their locations composed), or a
  // shape. The instance's own name and colour win over the product's.
  void Visit(const TDF_Label& label, const TopLoc_Location& location, std::string name,
             std::optional<std::array<double, 3>> colour, int depth) {
    if (depth > 64) return;  // a cycle of references in a broken file
    TDF_Label product = label;
    if (XCAFDoc_ShapeTool::IsReference(label)) XCAFDoc_ShapeTool::GetReferredShape(label, product);
    if (name.empty()) name = NameOf(product);
    if (!colour) colour = ColourOf(colours, label, XCAFDoc_ShapeTool::GetShape(label));
    if (!colour) colour = ColourOf(colours, product, XCAFDoc_ShapeTool::GetShape(product));
    if (XCAFDoc_ShapeTool::IsAssembly(product)) {
      TDF_LabelSequence components;
      XCAFDoc_ShapeTool::GetComponents(product, components);
      for (int i = 1; i <= components.Length(); ++i) {
        const TDF_Label& component = components.Value(i);
        TDF_Label referred;
        XCAFDoc_ShapeTool::GetReferredShape(component, referred);
        // A component is named by its product (the part), not by its instance name.
        Visit(component, location * XCAFDoc_ShapeTool::GetLocation(component), NameOf(referred),
              colour, depth + 1);
      }
      return;
    }
    TopoDS_Shape shape = XCAFDoc_ShapeTool::GetShape(product);
    if (shape.IsNull()) return;
    AddShape(shape.Moved(location), name, colour);
  }
};

std::vector<CadPart> ReadInProcess(const std::string& path, double deflection) {
  // OpenCASCADE prints its own traces to stdout: silenced, its failures are read below.
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_Printer));
  Handle(TDocStd_Document) document;
  XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", document);
  // Lengths in metres: the readers convert from the file's own unit.
  XCAFDoc_DocumentTool::SetLengthUnit(document, 1.0);
  const bool iges = IsIgesFile(path);
  const char* kind = iges ? "IGES" : "STEP";
  std::string failure;
  bool transferred = false;
  if (iges) {
    IGESCAFControl_Reader reader;
    reader.SetNameMode(true);
    reader.SetColorMode(true);
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
      Fail(path, fmt::format("not a {} file OpenCASCADE can read{}", kind,
                             [&] { const std::string f = FirstFailure(reader);
                                   return f.empty() ? std::string() : " (" + f + ")"; }()));
    failure = FirstFailure(reader);
    transferred = reader.Transfer(document);
  } else {
    STEPCAFControl_Reader reader;
    reader.SetNameMode(true);
    reader.SetColorMode(true);
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone) {
      const std::string f = FirstFailure(reader.ChangeReader());
      Fail(path, fmt::format("not a {} file OpenCASCADE can read{}", kind,
                             f.empty() ? std::string() : " (" + f + ")"));
    }
    failure = FirstFailure(reader.ChangeReader());
    transferred = reader.Transfer(document);
  }
  if (!transferred)
    Fail(path, fmt::format("OpenCASCADE read no shape from this {} file{}", kind,
                           failure.empty() ? std::string() : " (" + failure + ")"));
  Reader read;
  read.shapes = XCAFDoc_DocumentTool::ShapeTool(document->Main());
  read.colours = XCAFDoc_DocumentTool::ColorTool(document->Main());
  read.deflection = deflection;
  TDF_LabelSequence roots;
  read.shapes->GetFreeShapes(roots);
  for (int i = 1; i <= roots.Length(); ++i)
    read.Visit(roots.Value(i), TopLoc_Location(), {}, std::nullopt, 0);
  if (read.parts.empty())
    Fail(path, fmt::format("holds no solid or face that could be meshed{}",
                           failure.empty() ? std::string() : " (" + failure + ")"));
  return read.parts;
}

// The parts as bytes, for the trip out of the child process, and back.
std::string PartsBytes(const std::vector<CadPart>& parts) {
  std::string bytes;
  const auto put = [&](const void* p, size_t n) { bytes.append(static_cast<const char*>(p), n); };
  for (const CadPart& part : parts) {
    const uint64_t header[] = {part.name.size(), part.mesh.vertices.size(),
                               part.mesh.triangles.size(), part.colour ? 1u : 0u};
    put(header, sizeof(header));
    put(part.name.data(), part.name.size());
    const std::array<double, 3> colour = part.colour.value_or(std::array<double, 3>{});
    put(colour.data(), sizeof(colour));
    for (const Vec3& v : part.mesh.vertices) put(v.data(), 3 * sizeof(double));
    put(part.mesh.triangles.data(), part.mesh.triangles.size() * sizeof(part.mesh.triangles[0]));
  }
  return bytes;
}

}  // namespace
}  // namespace vantage::detail

/// The module's one entry (CadModuleEntry in step_reader.cpp): the parts of the CAD file at
/// `path` meshed to `deflection` metres, as bytes in `*parts`, and 0; or 1 and the reason in
/// `*failure` ("PATH: what"). Throws nothing.
extern "C" __attribute__((visibility("default"))) int vantage_read_cad(const char* path,
                                                                     double deflection,
                                                                     std::string* parts,
                                                                     std::string* failure) {
  using namespace vantage::detail;
  try {
    try {
      *parts = PartsBytes(ReadInProcess(path, deflection));
      return 0;
    } catch (const Standard_Failure& e) {
      Fail(path, fmt::format("OpenCASCADE failed on it: {}", e.GetMessageString()));
    }
  } catch (const std::exception& e) {
    *failure = e.what();
  } catch (...) {
    *failure = fmt::format("{}: OpenCASCADE failed on it", path);
  }
  return 1;
}
