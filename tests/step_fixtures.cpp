// Writes the CAD fixtures of tests/step_test.cpp with OpenCASCADE, from primitives whose areas
// are known analytically (run at build time: the project ships no CAD file it did not make).
//   step_fixtures DIR   writes into DIR:
//     box.step          a 100 x 200 x 300 mm box (lengths in mm: the reader converts to metres)
//     cylinder.step     a cylinder of radius 50 mm and height 120 mm
//     box.igs           the box as IGES
//     cell.step         an assembly "cell": a green "bracket" (40 x 40 x 10 mm box), a grey
//                       "plate" (200 x 100 x 5 mm box) and two instances of a "bolt" (cylinder of
//                       radius 5 mm, 20 mm high), each placed by its component's location
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <IGESControl_Controller.hxx>
#include <IGESControl_Writer.hxx>
#include <Quantity_Color.hxx>
#include <STEPCAFControl_Writer.hxx>
#include <TDataStd_Name.hxx>
#include <TDocStd_Document.hxx>
#include <TopLoc_Location.hxx>
#include <XCAFApp_Application.hxx>
#include <XCAFDoc_ColorTool.hxx>
#include <XCAFDoc_DocumentTool.hxx>
#include <XCAFDoc_ShapeTool.hxx>
#include <gp_Trsf.hxx>

#include <cstdio>
#include <string>

namespace {

Handle(TDocStd_Document) NewDocument() {
  Handle(TDocStd_Document) document;
  XCAFApp_Application::GetApplication()->NewDocument("MDTV-XCAF", document);
  XCAFDoc_DocumentTool::SetLengthUnit(document, 0.001);  // millimetres, as most CAD writes
  return document;
}

bool Write(const Handle(TDocStd_Document)& document, const std::string& path) {
  STEPCAFControl_Writer writer;
  writer.SetNameMode(true);
  writer.SetColorMode(true);
  return writer.Transfer(document, STEPControl_AsIs) && writer.Write(path.c_str()) == IFSelect_RetDone;
}

bool OneShape(const TopoDS_Shape& shape, const char* name, const std::string& path) {
  Handle(TDocStd_Document) document = NewDocument();
  const TDF_Label label = XCAFDoc_DocumentTool::ShapeTool(document->Main())->AddShape(shape, false);
  TDataStd_Name::Set(label, name);
  return Write(document, path);
}

TopLoc_Location At(double x, double y, double z) {
  gp_Trsf move;
  move.SetTranslation(gp_Vec(x, y, z));
  return TopLoc_Location(move);
}

bool Cell(const std::string& path) {
  Handle(TDocStd_Document) document = NewDocument();
  Handle(XCAFDoc_ShapeTool) shapes = XCAFDoc_DocumentTool::ShapeTool(document->Main());
  Handle(XCAFDoc_ColorTool) colours = XCAFDoc_DocumentTool::ColorTool(document->Main());
  const TDF_Label cell = shapes->NewShape();
  TDataStd_Name::Set(cell, "cell");
  const TDF_Label bracket = shapes->AddShape(BRepPrimAPI_MakeBox(40, 40, 10).Shape(), false);
  TDataStd_Name::Set(bracket, "bracket");
  colours->SetColor(bracket, Quantity_Color(0, 1, 0, Quantity_TOC_RGB), XCAFDoc_ColorSurf);
  const TDF_Label plate = shapes->AddShape(BRepPrimAPI_MakeBox(200, 100, 5).Shape(), false);
  TDataStd_Name::Set(plate, "plate");
  colours->SetColor(plate, Quantity_Color(0.5, 0.5, 0.5, Quantity_TOC_RGB), XCAFDoc_ColorSurf);
  const TDF_Label bolt = shapes->AddShape(BRepPrimAPI_MakeCylinder(5, 20).Shape(), false);
  TDataStd_Name::Set(bolt, "bolt");
  shapes->AddComponent(cell, bracket, At(80, 30, 5));
  shapes->AddComponent(cell, plate, At(0, 0, 0));
  shapes->AddComponent(cell, bolt, At(20, 20, 5));
  shapes->AddComponent(cell, bolt, At(180, 80, 5));
  shapes->UpdateAssemblies();
  return Write(document, path);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: step_fixtures DIR\n");
    return 2;
  }
  const std::string dir = argv[1];
  bool ok = OneShape(BRepPrimAPI_MakeBox(100, 200, 300).Shape(), "box", dir + "/box.step");
  ok = ok && OneShape(BRepPrimAPI_MakeCylinder(50, 120).Shape(), "cylinder", dir + "/cylinder.step");
  ok = ok && Cell(dir + "/cell.step");
  IGESControl_Controller::Init();
  IGESControl_Writer iges("MM", 1);  // faces as BRep entities
  iges.AddShape(BRepPrimAPI_MakeBox(100, 200, 300).Shape());
  iges.ComputeModel();
  ok = ok && iges.Write((dir + "/box.igs").c_str());
  if (!ok) std::fprintf(stderr, "step_fixtures: writing into %s failed\n", dir.c_str());
  return ok ? 0 : 1;
}
