// Small mesh / polyline files and PNG images for the apps fuzz targets (fuzz_mesh's seeds, and
// the files fuzz_scene's scenes may name), written with VTK's writers at run time: nothing binary
// is committed. Header-only: used by make_app_seeds and by fuzz_scene (which writes the assets
// into its own folder before the first input).
#pragma once

#include <vtkCellArray.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPLYWriter.h>
#include <vtkPNGWriter.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataWriter.h>
#include <vtkSmartPointer.h>
#include <vtkSTLWriter.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnsignedShortArray.h>
#include <vtkXMLPolyDataWriter.h>

#include <fstream>
#include <string>
#include <vector>

namespace wffuzz {

/// The formats of fuzz_mesh, in the order its first byte picks them (byte % 5).
inline const std::vector<std::string>& meshExtensions() {
  static const std::vector<std::string> e = {".vtp", ".vtk", ".stl", ".obj", ".ply"};
  return e;
}

/// A small polygonal data set with every kind of cell the readers turn into geometry: a cube of
/// quads, a triangle strip, a polygon, two polylines (one of 2 points), a vertex, and uchar RGB
/// point colours. `lines` only: the two polylines.
inline vtkSmartPointer<vtkPolyData> makePolyData(bool withPolys, bool withLines, bool colours) {
  auto pd = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  const double c[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  for (const auto& p : c) pts->InsertNextPoint(p);
  for (int i = 0; i < 4; ++i) pts->InsertNextPoint(2.0 + 0.5 * i, 0.25 * (i % 2), 0.5);  // 8..11: strip / lines
  pd->SetPoints(pts);
  if (withPolys) {
    vtkNew<vtkCellArray> polys;
    const vtkIdType q[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
    for (const auto& f : q) polys->InsertNextCell(4, f);
    const vtkIdType tri[3] = {8, 9, 10};
    polys->InsertNextCell(3, tri);
    pd->SetPolys(polys);
    vtkNew<vtkCellArray> strips;
    const vtkIdType s[4] = {8, 9, 10, 11};
    strips->InsertNextCell(4, s);
    pd->SetStrips(strips);
    vtkNew<vtkCellArray> verts;
    const vtkIdType v[1] = {11};
    verts->InsertNextCell(1, v);
    pd->SetVerts(verts);
  }
  if (withLines) {
    vtkNew<vtkCellArray> lines;
    const vtkIdType l0[4] = {8, 9, 10, 11};
    const vtkIdType l1[2] = {0, 6};
    lines->InsertNextCell(4, l0);
    lines->InsertNextCell(2, l1);
    pd->SetLines(lines);
  }
  if (colours) {
    vtkNew<vtkUnsignedCharArray> rgb;
    rgb->SetName("RGB");
    rgb->SetNumberOfComponents(3);
    for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i)
      rgb->InsertNextTuple3(40 + 17 * i, 200 - 13 * i, 90 + 11 * i);
    pd->GetPointData()->SetScalars(rgb);
  }
  return pd;
}

inline void writeText(const std::string& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

/// An OBJ written by hand: vertices, texture coordinates, normals, faces in the three index
/// forms, a negative (relative) index, a line and a group.
inline std::string objText() {
  return "# WireFur fuzz seed\n"
         "o cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
         "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
         "vn 0 0 -1\nvn 0 0 1\nvn 0 -1 0\nvn 1 0 0\n"
         "g bottom\nf 1/1/1 4/4/1 3/3/1 2/2/1\nf 5/1/2 6/2/2 7/3/2 8/4/2\n"
         "g sides\nf 1//3 2//3 6//3 5//3\nf 2/2 3/3 7/3 6/2\nf 3 4 8 7\nf -8 -4 -1 -5\n"
         "l 1 7\nl 2 3 4\n";
}

/// Writes one mesh file of each format and flavour into `dir` (names: mesh*.EXT, lines.vtp)
/// and returns their names.
inline std::vector<std::string> writeMeshFiles(const std::string& dir) {
  std::vector<std::string> names;
  auto full = makePolyData(true, true, true);
  auto polysOnly = makePolyData(true, false, false);
  auto linesOnly = makePolyData(false, true, false);
  auto xml = [&](const std::string& name, vtkPolyData* pd, int mode, bool compress) {
    vtkNew<vtkXMLPolyDataWriter> w;
    w->SetFileName((dir + "/" + name).c_str());
    w->SetInputData(pd);
    if (mode == 0) w->SetDataModeToAscii();
    else if (mode == 1) w->SetDataModeToBinary();
    else w->SetDataModeToAppended(), w->EncodeAppendedDataOff();
    if (!compress) w->SetCompressorTypeToNone();
    if (w->Write()) names.push_back(name);
  };
  xml("mesh.vtp", full, 2, false);
  xml("mesh_ascii.vtp", full, 0, false);
  xml("mesh_zlib.vtp", polysOnly, 1, true);
  xml("lines.vtp", linesOnly, 0, false);
  auto legacy = [&](const std::string& name, vtkPolyData* pd, bool binary) {
    vtkNew<vtkPolyDataWriter> w;
    w->SetFileName((dir + "/" + name).c_str());
    w->SetInputData(pd);
    if (binary) w->SetFileTypeToBinary();
    else w->SetFileTypeToASCII();
    if (w->Write()) names.push_back(name);
  };
  legacy("mesh.vtk", full, false);
  legacy("mesh_binary.vtk", full, true);
  legacy("lines.vtk", linesOnly, false);
  auto stl = [&](const std::string& name, bool binary) {
    vtkNew<vtkSTLWriter> w;
    w->SetFileName((dir + "/" + name).c_str());
    w->SetInputData(polysOnly);
    if (binary) w->SetFileTypeToBinary();
    else w->SetFileTypeToASCII();
    if (w->Write()) names.push_back(name);
  };
  stl("mesh.stl", true);
  stl("mesh_ascii.stl", false);
  auto ply = [&](const std::string& name, vtkPolyData* pd, int mode) {
    vtkNew<vtkPLYWriter> w;
    w->SetFileName((dir + "/" + name).c_str());
    w->SetInputData(pd);
    if (mode == 0) w->SetFileTypeToASCII();
    else w->SetFileTypeToBinary();
    if (mode == 2) w->SetDataByteOrderToBigEndian();
    w->SetArrayName("RGB");
    w->SetColorModeToDefault();
    if (w->Write()) names.push_back(name);
  };
  ply("mesh.ply", full, 1);
  ply("mesh_ascii.ply", full, 0);
  ply("mesh_big_endian.ply", polysOnly, 2);
  writeText(dir + "/mesh.obj", objText());
  names.push_back("mesh.obj");
  writeText(dir + "/lines.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 1\nl 1 2 3 4\nl 4 1\n");
  names.push_back("lines.obj");
  return names;
}

/// Small PNG images for textures and bump maps: tex.png (8 x 8 RGB, 8 bits), bump.png (8 x 8
/// grey, 16 bits).
inline void writeImages(const std::string& dir) {
  {
    vtkNew<vtkImageData> im;
    im->SetDimensions(8, 8, 1);
    im->AllocateScalars(VTK_UNSIGNED_CHAR, 3);
    auto* p = static_cast<unsigned char*>(im->GetScalarPointer());
    for (int i = 0; i < 8 * 8 * 3; ++i) p[i] = static_cast<unsigned char>((i * 37) & 255);
    vtkNew<vtkPNGWriter> w;
    w->SetFileName((dir + "/tex.png").c_str());
    w->SetInputData(im);
    w->Write();
  }
  {
    vtkNew<vtkImageData> im;
    im->SetDimensions(8, 8, 1);
    im->AllocateScalars(VTK_UNSIGNED_SHORT, 1);
    auto* p = static_cast<unsigned short*>(im->GetScalarPointer());
    for (int i = 0; i < 8 * 8; ++i) p[i] = static_cast<unsigned short>(i * 1021);
    vtkNew<vtkPNGWriter> w;
    w->SetFileName((dir + "/bump.png").c_str());
    w->SetInputData(im);
    w->Write();
  }
}

}  // namespace wffuzz
