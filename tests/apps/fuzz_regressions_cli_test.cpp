// Inputs the scene and mesh fuzz targets found (tests/fuzz: fuzz_scene, fuzz_mesh), kept as
// command-line regression tests: each is bad input, so `wirefur render` reports it as one line
// naming the file and the problem, exit status 2, within seconds, and writes no image
// (tests/apps/scene_regressions/README.md, tests/apps/mesh_regressions/README.md).
#include "cli_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Case {
  std::string file;    ///< under tests/apps/
  std::string expect;  ///< part of the one-line message
};

// `c.file` is under tests/apps/, or an absolute path (a file written by the test).
void expectCleanFailure(const Case& c) {
  const fs::path png = wf::test::scratchDir("wirefur-fuzz-regressions") / "out.png";
  fs::remove(png);
  const std::string input = fs::path(c.file).is_absolute() ? c.file : std::string(WIREFUR_SOURCE_DIR) + "/tests/apps/" + c.file;
  const auto t0 = std::chrono::steady_clock::now();
  const wf::test::CliResult r = wf::test::runWirefur("render '" + input + "' -o '" + png.string() + "' --size 64x48");
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_EQ(r.status, 2) << c.file << ": " << r.err;
  EXPECT_EQ(wf::test::lineCount(r.err), 1) << c.file << ": " << r.err;
  EXPECT_NE(r.err.find(fs::path(c.file).filename().string()), std::string::npos) << c.file << ": " << r.err;
  EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.file << ": " << r.err;
  EXPECT_FALSE(fs::exists(png)) << c.file;
  EXPECT_LT(secs, 30.0) << c.file;
}

}  // namespace

TEST(FuzzRegressions, MeshFiles) {
  const Case cases[] = {
      // No "vertex" element: VTK's PLY reader closed the file and read on from it (SIGSEGV).
      {"mesh_regressions/ply_no_vertex_element.ply", "no vertex element with x, y and z"},
      // Out-of-range indices VTK's OBJ reader resolved unchecked (SEGV, bad-free,
      // alloc-dealloc mismatch): texture coordinates are looked up at once, normals and vertices
      // copied by index where a face indexes them apart; "l" and "p" too.
      {"mesh_regressions/obj_texcoord_index_out_of_range.obj", ":5: f: texture coordinate index 900000 out of range 1..1"},
      {"mesh_regressions/obj_texcoord_index_negative.obj", ":5: f: relative texture coordinate index -5"},
      {"mesh_regressions/obj_normal_index_out_of_range.obj", ":5: f: normal index 90000 out of range 1..1"},
      {"mesh_regressions/obj_vertex_index_out_of_range.obj", ":5: f: vertex index 90000 out of range 1..3"},
      {"mesh_regressions/obj_vertex_index_relative_before_first.obj", ":4: f: relative vertex index -9"},
      {"mesh_regressions/obj_vertex_index_zero.obj", ":4: f: vertex index 0"},
      {"mesh_regressions/obj_line_index_out_of_range.obj", ":4: l: vertex index 9 out of range 1..3"},
      {"mesh_regressions/obj_continuation_texcoord_out_of_range.obj", ":6: f: texture coordinate index 7 out of range"},
      // "usemtl" names go into VTK's char[100] with sscanf("%s").
      {"mesh_regressions/obj_material_name_too_long.obj", ":5: material name longer than 99 characters"},
      // VTK's PLY reader: face indices past the vertices (SEGV in vtkCell::Initialize), and the
      // records it cannot read, which leave its face uninitialised (free() of a wild pointer).
      {"mesh_regressions/ply_face_index_out_of_range.ply", ":13: face 0: index 5 out of range 0..2"},
      {"mesh_regressions/ply_face_index_negative.ply", ":13: face 0: index -1 out of range 0..2"},
      {"mesh_regressions/ply_face_negative_list_count.ply", ":13: face 0: list 'vertex_indices' has a bad length"},
      {"mesh_regressions/ply_face_list_count_past_line.ply", ":13: PLY face line has too few values"},
      {"mesh_regressions/ply_face_line_without_newline.ply", ":13: PLY face line has no newline"},
      {"mesh_regressions/ply_face_empty_line.ply", ":13: PLY face line has too few values"},
      {"mesh_regressions/ply_face_before_vertex.ply", "the face element comes before the vertex element"},
      {"mesh_regressions/ply_face_without_vertex_indices.ply", "the face element has no 'vertex_indices' list"},
      {"mesh_regressions/ply_header_blank_line.ply", ":4: PLY header: empty line"},
      // An element without properties: VTK frees its never-set property list (fuzz_mesh, ASan).
      {"mesh_regressions/ply_element_without_properties.ply", "element ';ace' has no properties"},
      // Legacy .vtk cell offsets past the connectivity: the cell walk read out of range (VTK's
      // assert in fuzz_mesh's build).
      {"mesh_regressions/vtk_cell_offsets_past_connectivity.vtk", "polygon cells: offset 1 (7) does not fit"},
      // Counts that ask for terabytes: std::bad_alloc inside VTK's reader was an internal error
      // (ASan aborts on the allocation itself): refused before VTK sizes its arrays.
      {"mesh_regressions/vtp_points_count_too_large.vtp", "NumberOfPoints \"900000000000000\" is not a count"},
  };
  for (const Case& c : cases) expectCleanFailure(c);
}

namespace {

// A binary PLY file of three vertices (x, y, z float) and the given face records, in either
// byte order; the face element is "list <countType> <indexType> vertex_indices".
struct BinaryPly {
  explicit BinaryPly(bool be) : bigEndian(be) {}
  bool bigEndian;
  std::string countType = "uchar", indexType = "int";
  std::string body;
  void put(const void* p, size_t n) {
    std::string b(static_cast<const char*>(p), n);
    if (bigEndian) std::reverse(b.begin(), b.end());
    body += b;
  }
  void u8(std::uint8_t v) { put(&v, 1); }
  void i8(std::int8_t v) { put(&v, 1); }
  void i32(std::int32_t v) { put(&v, 4); }
  void u32(std::uint32_t v) { put(&v, 4); }
  void f32(float v) { put(&v, 4); }
  std::string file(int faces) {
    std::string h = std::string("ply\nformat ") + (bigEndian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face " +
                    std::to_string(faces) + "\nproperty list " + countType + " " + indexType + " vertex_indices\nend_header\n";
    return h + body;
  }
  void vertices() {
    for (float v : {0.f, 0.f, 0.f, 1.f, 0.f, 0.f, 0.f, 1.f, 0.f}) f32(v);
  }
};

}  // namespace

// Binary PLY, both byte orders: the same faults, found by walking the vertex records by their
// property sizes and then each face's count and indices (written here at run time, not committed).
TEST(FuzzRegressions, BinaryPlyFiles) {
  const fs::path dir = wf::test::scratchDir("wirefur-fuzz-regressions-ply");
  for (bool be : {false, true}) {
    const std::string order = be ? "be" : "le";
    std::vector<Case> cases;
    auto add = [&](const std::string& name, const std::string& bytes, const std::string& expect) {
      cases.push_back({wf::test::writeFile(dir, name + "_" + order + ".ply", bytes), expect});
    };
    {  // a valid file reads: the check does not refuse it
      BinaryPly p(be);
      p.vertices();
      p.u8(3), p.i32(0), p.i32(1), p.i32(2);
      const std::string ok = wf::test::writeFile(dir, "ok_" + order + ".ply", p.file(1));
      const fs::path png = dir / ("ok_" + order + ".png");
      const wf::test::CliResult r = wf::test::runWirefur("render '" + ok + "' -o '" + png.string() + "' --size 32x24");
      EXPECT_EQ(r.status, 0) << r.err;
      EXPECT_TRUE(fs::exists(png));
    }
    {
      BinaryPly p(be);
      p.vertices();
      p.u8(3), p.i32(0), p.i32(1), p.i32(2);
      p.u8(3), p.i32(0), p.i32(1), p.i32(70000);
      add("index_past_vertices", p.file(2), ": face 1: index 70000 out of range 0..2");
    }
    {
      BinaryPly p(be);
      p.indexType = "uint";
      p.vertices();
      p.u8(3), p.u32(0), p.u32(1), p.u32(0xFFFFFFFFu);
      add("index_uint_negative", p.file(1), ": face 0: index");
    }
    {
      BinaryPly p(be);
      p.countType = "char";
      p.vertices();
      p.i8(-1), p.i32(0), p.i32(1), p.i32(2);
      add("negative_count", p.file(1), ": face 0: list 'vertex_indices' has a bad length");
    }
    {
      BinaryPly p(be);
      p.countType = "int";
      p.vertices();
      p.i32(1000000), p.i32(0), p.i32(1), p.i32(2);
      add("count_past_end", p.file(1), ": PLY body ends inside face 0");
    }
    {
      BinaryPly p(be);
      p.vertices();
      p.u8(3), p.i32(0), p.i32(1), p.i32(2);
      p.u8(3), p.i32(0);
      add("truncated_face", p.file(2), ": PLY body ends inside face 1");
    }
    for (const Case& c : cases) expectCleanFailure(c);
  }
}

TEST(FuzzRegressions, Scenes) {
  const Case cases[] = {
      // Wires were not counted in the scene's budget of primitives: four spheres' edges (433
      // bytes) made 12 million segments, 40 objects of isolines 21 million (8-10 GB in render).
      {"scene_regressions/edges_unbudgeted.json", "/objects/1/wire: this wire's edges would make about"},
      {"scene_regressions/isolines_unbudgeted.json", "/wire: this wire would make about"},
  };
  for (const Case& c : cases) expectCleanFailure(c);
}

// A scene key with a newline in it (fuzz_scene, CI): the message quoting its JSON pointer was two
// lines. Control characters in what a message quotes are written out (\n, \x01), in keys, values
// and the file's own name.
TEST(FuzzRegressions, ControlCharactersStayOnOneLine) {
  const fs::path dir = wf::test::scratchDir("wirefur-fuzz-regressions-ctl");
  const std::string scene = R"({"objects": [{"source": {"type": "torus"}, "fur": {"d\nx": 1}}]})";
  expectCleanFailure({wf::test::writeFile(dir, "key_newline.json", scene), "/objects/0/fur/d\\nx: unknown key"});
  const std::string value = R"({"objects": [{"source": {"type": "tor\u0001us"}}]})";
  expectCleanFailure({wf::test::writeFile(dir, "value_control.json", value), "'tor\\x01us' is not one of"});

  const fs::path png = dir / "out.png";
  fs::remove(png);
  const std::string named = wf::test::writeFile(dir, "two\nlines.json", scene);
  const wf::test::CliResult r = wf::test::runWirefur("render '" + named + "' -o '" + png.string() + "' --size 32x24");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("two\\nlines.json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(png));
}
