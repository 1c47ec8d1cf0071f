// `wirefur render | export | view` on CAD files (docs/cad.md), as users call them: the three
// styles of the contract on data/cad/mould.step and product.step (made by data/cad/make_samples.cpp
// with OpenCASCADE), the counts and deflection in --stats against what the files hold, bad input
// as one line with exit status 2 and nothing written, determinism across thread counts, and
// OpenCASCADE kept out of the executable's link (it is opened only for CAD input).
#include "cli_support.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <signal.h>
#include <unistd.h>

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkImageData.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkMath.h>
#include <vtkNew.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLPolyDataReader.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>
#include <sstream>
#include <set>
#include <string>

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

using Result = wf::test::CliResult;
Result run(const std::string& args) { return wf::test::runWirefur(args); }

fs::path dir() { return wf::test::scratchDir("wirefur-cad-cli"); }
std::string slurp(const fs::path& p) { return wf::test::readFile(p); }
std::string write(const std::string& name, const std::string& bytes) { return wf::test::writeFile(dir(), name, bytes); }

const std::string kCad = std::string(WIREFUR_SOURCE_DIR) + "/data/cad/";

json renderStats(const std::string& input, const std::string& extra, const std::string& tag) {
  const fs::path png = dir() / (tag + ".png"), stats = dir() / (tag + ".json");
  const Result r = run("render '" + input + "' -o '" + png.string() + "' --size 240x180 --stats '" + stats.string() + "' " + extra);
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(png));
  if (!fs::exists(stats)) return json::object();
  return json::parse(slurp(stats));
}

}  // namespace

// mould.step holds two parts (an XCAF assembly of two named, coloured solids): 46 faces and 96
// edges, counted by OpenCASCADE when the file was made. Each style draws what the contract says.
TEST(CadCli, ThreeStylesDrawWhatTheySay) {
  const json wos = renderStats(kCad + "mould.step", "", "wos");
  ASSERT_TRUE(wos.contains("input"));
  const json& cad = wos["input"]["cad"];
  EXPECT_EQ(cad["parts"], 2);
  EXPECT_EQ(cad["faces"], 46);
  EXPECT_EQ(cad["faces_meshed"], 46);
  EXPECT_EQ(cad["faces_skipped"], 0);
  EXPECT_EQ(cad["edges"], 96);
  EXPECT_GT(wos["triangles"].get<long>(), 46);
  EXPECT_GT(wos["segments"].get<long>(), 96);
  // The default deflection is 1e-3 of the model's diagonal (exactly, up to rounding).
  EXPECT_NEAR(cad["linear_deflection_relative"].get<double>(), 1e-3, 1e-15);
  EXPECT_NEAR(cad["linear_deflection"].get<double>(), 1e-3 * cad["model_size"].get<double>(), 1e-12);
  // Reported in pixels too; at 240x180 a thousandth of the model is well under a pixel.
  const double px = wos["error_estimate"]["tessellation_deflection_px"].get<double>();
  EXPECT_GT(px, 0.0);
  EXPECT_LT(px, 0.5);

  const json wire = renderStats(kCad + "mould.step", "--style wire", "wire");
  EXPECT_EQ(wire["triangles"], 0);  // edges only
  EXPECT_EQ(wire["segments"], wos["segments"]);
  const json steel = renderStats(kCad + "mould.step", "--style burnished", "steel");
  EXPECT_EQ(steel["segments"], 0);  // surfaces only
  EXPECT_EQ(steel["triangles"], wos["triangles"]);
  EXPECT_GT(steel["left_out"]["lobe_tables_built"].get<long>(), 0);  // grain shades as cylinders, closed form
  EXPECT_LT(steel["error_estimate"]["shading_bound"].get<double>(), 2e-3);
}

// A coarser relative deflection gives fewer triangles, and the stats report the value asked for.
TEST(CadCli, DeflectionOptionsChangeTheTessellation) {
  const json fine = renderStats(kCad + "product.step", "--style burnished", "fine");
  const json coarse = renderStats(kCad + "product.step", "--style burnished --deflection 0.01 --angular-deflection 40", "coarse");
  EXPECT_LT(coarse["triangles"].get<long>(), fine["triangles"].get<long>());
  EXPECT_NEAR(coarse["input"]["cad"]["linear_deflection_relative"].get<double>(), 0.01, 1e-15);
  EXPECT_NEAR(coarse["input"]["cad"]["angular_deflection_degrees"].get<double>(), 40.0, 1e-9);
  const json abs = renderStats(kCad + "product.step", "--style burnished --linear-deflection 0.25", "abs");
  EXPECT_NEAR(abs["input"]["cad"]["linear_deflection"].get<double>(), 0.25, 1e-15);
  // Iso lines: 2 u and 2 v lines on each of the tray's 35 faces (more pieces where faces are
  // trimmed, none where an iso misses a face); each is a polyline of its own.
  const json isos = renderStats(kCad + "product.step", "--style wire --isos 2", "isos");
  EXPECT_GT(isos["input"]["cad"]["iso_lines"].get<long>(), 35);
  EXPECT_GT(isos["segments"].get<long>(), fine["input"]["cad"]["edges"].get<long>());
}

// Fur on the exact faces: area-correct roots at a density of 60,000 per total face area, only where
// each face is (its trimming as the density map). The count is a sum of Poisson-like draws per
// cell (sd about 245); 2,000 also allows for the cells at trimmed edges whose bound sees no inside
// sample. Three segments per hair.
TEST(CadCli, FurGrowsOnTheExactFaces) {
  const json fur = renderStats(kCad + "product.step", "--style fur", "fur");
  const long hairs = fur["generated"]["hairs"].get<long>();
  EXPECT_NEAR(double(hairs), 60000.0, 2000.0);
  EXPECT_EQ(fur["segments"].get<long>(), 3 * hairs);
  EXPECT_GT(fur["triangles"].get<long>(), 0);  // the tray's surfaces under the fur
}

// Every style on a STEP and a BREP file, with the presets' materials (docs/scenes.md, "Styles");
// scales grow on the exact faces, trimmed like fur.
TEST(CadCli, EveryStyleOnStepAndBrep) {
  const std::string brep = std::string(WIREFUR_SOURCE_DIR) + "/tests/apps/cad_regressions/binary_brep_from_BinTools_Write.brep";
  for (const std::string& input : {kCad + "product.step", brep}) {
    SCOPED_TRACE(input);
    auto names = [](const json& s) {
      std::set<std::string> m;
      for (const json& n : s.value("materials", json::array())) m.insert(n.get<std::string>());
      return m;
    };
    const json wire = renderStats(input, "--style wire", "s_wire");
    EXPECT_EQ(names(wire), std::set<std::string>({"wire"}));
    const json steel = renderStats(input, "--style burnished", "s_steel");
    EXPECT_EQ(names(steel), std::set<std::string>({"brushed steel"}));
    const json scales = renderStats(input, "--style scales", "s_scales");
    EXPECT_EQ(names(scales), std::set<std::string>({"skin", "scale"}));
    EXPECT_GT(scales["generated"]["scales"].get<long>(), 100);
    const json fur = renderStats(input, "--style fur", "s_fur");
    EXPECT_EQ(names(fur), std::set<std::string>({"fur skin", "fur"}));
  }
}

// Same input, same image, bit for bit, for 1 and 2 threads (meshing and faces run in parallel).
TEST(CadCli, SameImageForAnyThreadCount) {
  const fs::path a = dir() / "t1.png", b = dir() / "t2.png";
  ASSERT_EQ(run("render '" + kCad + "mould.step' -o '" + a.string() + "' --size 200x150 --threads 1").status, 0);
  ASSERT_EQ(run("render '" + kCad + "mould.step' -o '" + b.string() + "' --size 200x150 --threads 2").status, 0);
  EXPECT_EQ(slurp(a), slurp(b));
}

// Bad CAD input: one line naming the file and the problem, exit status 2, no PNG.
TEST(CadCli, BadInputIsOneLineExitTwoAndNothingWritten) {
  const std::string step = slurp(kCad + "product.step");
  struct Case {
    std::string file, expect;
  } cases[] = {
      {(dir() / "missing.step").string(), "no such file"},
      {write("empty.step", ""), "empty file"},
      {write("text.step", "hello, I am not a STEP file\n"), "not a STEP file"},
      {write("truncated.step", step.substr(0, step.size() / 2)), ""},
      {write("png.step", std::string("\x89PNG\r\n\x1a\n", 8) + std::string(64, '\0')), "not a STEP file"},
      {write("noise.igs", std::string(200, 'x')), "not an IGES file"},
      {write("noise.brep", "random words\n"), "not a BREP file"},
      {write("bad.brep", "CASCADE Topology V3, (c) Open Cascade\nLocations 1\n1\n 1 2 3\n"), ""},
      {write("notzip.FCStd", "PK but not a zip"), "zip"},
  };
  for (const Case& c : cases) {
    const fs::path png = dir() / "bad.png";
    fs::remove(png);
    const Result r = run("render '" + c.file + "' -o '" + png.string() + "'");
    EXPECT_EQ(r.status, 2) << c.file << ": " << r.err;
    EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(c.file), std::string::npos) << r.err;
    if (!c.expect.empty()) {
      EXPECT_NE(r.err.find(c.expect), std::string::npos) << r.err;
    }
    EXPECT_FALSE(fs::exists(png)) << c.file;
  }
  // A cad block on a mesh object.
  write("tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  const std::string scene = write("cadkey.json", R"({"objects": [{"file": "tri.obj", "cad": {"isos": 2}}]})");
  const Result key = run("render '" + scene + "' -o '" + (dir() / "k.png").string() + "'");
  EXPECT_EQ(key.status, 2);
  EXPECT_NE(key.err.find("/objects/0/cad"), std::string::npos) << key.err;
}

// Inputs fuzzing found (tests/apps/cad_regressions/README.md): a crash inside OpenCASCADE, two
// hangs and a 2 GiB allocation are each one line with exit status 2 within seconds (the crash
// through the worker process), the fan-out document and the binary BREP read.
TEST(CadCli, FuzzFindings) {
  const std::string dirIn = std::string(WIREFUR_SOURCE_DIR) + "/tests/apps/cad_regressions/";
  const fs::path png = dir() / "fuzz.png";
  struct Case {
    std::string file;
    int status;
    std::string expect;
  } cases[] = {
      {"step_segv_cartesianpoint.step", 2, "OpenCASCADE crashed reading this file ("},
      {"iges_segv_face_nbloops.iges", 2, "OpenCASCADE crashed reading this file ("},
      {"brep_segv_in_mesher.brep", 2, "OpenCASCADE crashed reading this file ("},
      {"fcstd_segv_trimmed_curve.FCStd", 2, "OpenCASCADE crashed reading this file ("},
      {"brep_hang_one_char_mutation.brep", 2, "corrupt BREP"},
      {"fcstd_lying_size_2GiB_allocation.FCStd", 2, "truncated entry"},
      {"fcstd_container_fanout_hang.FCStd", 0, ""},
      {"binary_brep_from_BinTools_Write.brep", 0, ""},
  };
  for (const Case& c : cases) {
    fs::remove(png);
    const auto t0 = std::chrono::steady_clock::now();
    const Result r = run("render '" + dirIn + c.file + "' -o '" + png.string() + "' --size 64x48 --cad-timeout 60");
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    EXPECT_EQ(r.status, c.status) << c.file << ": " << r.err;
    EXPECT_LT(secs, 30.0) << c.file;
    if (c.status == 2) {
      EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
      EXPECT_NE(r.err.find(c.expect), std::string::npos) << r.err;
      EXPECT_FALSE(fs::exists(png)) << c.file;
    } else {
      EXPECT_TRUE(fs::exists(png)) << c.file;
    }
  }
}

// A reading that runs past --cad-timeout is stopped: one line naming the limit, exit status 2.
// A deflection of 1e-6 of the model makes meshing the mould take far longer than 0.1 s.
TEST(CadCli, TimeLimitStopsTheWorker) {
  const fs::path png = dir() / "slow.png";
  const Result r = run("render '" + kCad + "mould.step' -o '" + png.string() + "' --deflection 0.000001 --cad-timeout 0.1");
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
  EXPECT_NE(r.err.find("did not finish within 0.1 s"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(png));
}

// Bad CAD options, on the command line and in a scene's cad block: NaN, zero, out of range,
// overflow, negative, not a number. One line naming the option (or the JSON pointer), exit 2,
// and no PNG.
TEST(CadCli, BadCadOptionsAreOneLineExitTwo) {
  const fs::path png = dir() / "opt.png";
  const std::string in = "'" + kCad + "product.step' -o '" + png.string() + "' ";
  struct Case {
    std::string args, expect;
  } cases[] = {
      {"--deflection nan", "option --deflection"},     {"--deflection 0", "option --deflection"},
      {"--deflection 1e400", "option --deflection"},   {"--linear-deflection -1", "option --linear-deflection"},
      {"--angular-deflection 90", "option --angular-deflection"}, {"--isos -1", "option --isos"},
      {"--isos 1001", "option --isos"},                {"--cad-timeout 0", "option --cad-timeout"},
      {"--deflection", "needs a value"},
  };
  for (const Case& c : cases) {
    fs::remove(png);
    const Result r = run("render " + in + c.args);
    EXPECT_EQ(r.status, 2) << c.args << ": " << r.err;
    EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(c.expect), std::string::npos) << c.args << ": " << r.err;
    EXPECT_FALSE(fs::exists(png)) << c.args;
  }
  for (const auto& [block, pointer] : std::vector<std::pair<std::string, std::string>>{
           {R"({"deflection": -1})", "/objects/0/cad/deflection"},
           {R"({"isos": "two"})", "/objects/0/cad/isos"},
           {R"({"deflection": 0.001, "linear_deflection": 1})", "/objects/0/cad"}}) {
    const std::string scene = write("cadblock.json", R"({"objects": [{"file": ")" + kCad + R"(product.step", "cad": )" + block + "}]}");
    const Result r = run("render '" + scene + "' -o '" + png.string() + "'");
    EXPECT_EQ(r.status, 2) << block << ": " << r.err;
    EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find(pointer), std::string::npos) << block << ": " << r.err;
  }
}

// --hidden (docs/cad.md, "Hidden lines"): in the wire style, hide, dashed and ghost add the
// part's faces as hold-outs (triangles set up, nothing of them drawn); dashed and ghost keep x-ray
// copies of the edges' fragments, off and hide none; each mode draws a different picture; a
// scene file's wire takes the same modes as a key. Bad values: one line, exit 2, nothing written.
TEST(CadCli, HiddenLineModes) {
  const std::string in = kCad + "product.step";
  const json off = renderStats(in, "--style wire", "h_off");
  const json hide = renderStats(in, "--style wire --hidden hide", "h_hide");
  const json dashed = renderStats(in, "--style wire --hidden dashed=5,3", "h_dashed");
  const json ghost = renderStats(in, "--style wire --hidden ghost=0.4", "h_ghost");
  EXPECT_EQ(off["triangles"], 0);
  EXPECT_GT(hide["triangles"].get<long>(), 0);
  EXPECT_EQ(hide["triangles"], dashed["triangles"]);
  EXPECT_EQ(off["hidden_line_fragments"], 0);
  EXPECT_EQ(hide["hidden_line_fragments"], 0);
  EXPECT_GT(dashed["hidden_line_fragments"].get<long>(), 0);
  // the same copies but those wholly in a gap, which are not kept
  EXPECT_LT(dashed["hidden_line_fragments"].get<long>(), ghost["hidden_line_fragments"].get<long>());
  EXPECT_GT(dashed["hidden_line_fragments"].get<long>(), ghost["hidden_line_fragments"].get<long>() / 2);
  const std::set<std::string> pictures{slurp(dir() / "h_off.png"), slurp(dir() / "h_hide.png"), slurp(dir() / "h_dashed.png"),
                                       slurp(dir() / "h_ghost.png")};
  EXPECT_EQ(pictures.size(), 4u);
  // Over the drawn part (wire-over-surface), hide is the default picture.
  renderStats(in, "", "h_wos");
  renderStats(in, "--hidden hide", "h_wos_hide");
  EXPECT_EQ(slurp(dir() / "h_wos.png"), slurp(dir() / "h_wos_hide.png"));
  const std::string scene = write("hidden.json", R"({"objects": [{"file": ")" + in +
                                                     R"(", "surface": {"holdout": true}, "wire": {"from": "edges", "hidden": {"mode": "dashed", "dash": 5, "gap": 3}}}]})");
  const json keyed = renderStats(scene, "", "h_key");
  EXPECT_GT(keyed["hidden_line_fragments"].get<long>(), 0);
  const fs::path png = dir() / "h_bad.png";
  for (const std::string bad : {"dashes", "dashed=0,4", "dashed=6", "ghost=2", "ghost=x", "hide=1", ""}) {
    fs::remove(png);
    const Result r = run("render '" + in + "' -o '" + png.string() + "' --hidden '" + bad + "'");
    EXPECT_EQ(r.status, 2) << bad << ": " << r.err;
    EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("--hidden"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(png));
  }
  for (const std::string bad : {R"("dashes")", R"({"mode": "dashed", "dash": 0})", R"({"mode": "ghost", "opacity": 3})", R"({"dash": 4})",
                            R"({"mode": "ghost", "dash": 5})", R"({"mode": "off", "opacity": 0.5})"}) {
    const std::string s = write("hidden_bad.json", R"({"objects": [{"file": ")" + in + R"(", "wire": {"hidden": )" + bad + "}}]}");
    const Result r = run("render '" + s + "' -o '" + png.string() + "'");
    EXPECT_EQ(r.status, 2) << bad << ": " << r.err;
    EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
    EXPECT_NE(r.err.find("/objects/0/wire/hidden"), std::string::npos) << bad << ": " << r.err;
  }
}

// --silhouettes (docs/cad.md, "Silhouettes"): on by default for the wire styles of a CAD file,
// traced from its exact faces for the camera and counted in --stats; off draws the edges alone;
// a scene file's wire asks for them on a parametric source (a torus: two or more curves).
TEST(CadCli, SilhouettesOfCurvedFaces) {
  const std::string in = kCad + "product.step";
  const json on = renderStats(in, "--style wire", "sil_on");
  const json off = renderStats(in, "--style wire --silhouettes off", "sil_off");
  ASSERT_TRUE(on.contains("silhouettes")) << on.dump();
  EXPECT_FALSE(off.contains("silhouettes"));
  EXPECT_GT(on["silhouettes"]["faces"].get<long>(), 0);
  EXPECT_GT(on["silhouettes"]["curves"].get<long>(), 0);
  EXPECT_EQ(on["silhouettes"]["non_finite"], 0);
  EXPECT_GT(on["segments"].get<long>(), off["segments"].get<long>());
  EXPECT_EQ(on["error_estimate"]["silhouette_chord_px"], 0.1);
  const json steel = renderStats(in, "--style burnished", "sil_steel");
  EXPECT_FALSE(steel.contains("silhouettes"));
  const std::string scene = write("sil.json", R"({"objects": [{"source": {"type": "torus", "major": 1, "minor": 0.35}, "surface": false,
    "wire": {"from": "isolines", "lines": [4, 2], "thickness": 1.5, "units": "pixels", "silhouettes": true}}]})");
  const json torus = renderStats(scene, "", "sil_torus");
  ASSERT_TRUE(torus.contains("silhouettes"));
  EXPECT_GE(torus["silhouettes"]["curves"].get<long>(), 2);
  const fs::path png = dir() / "sil_bad.png";
  const Result r = run("render '" + in + "' -o '" + png.string() + "' --silhouettes maybe");
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
  EXPECT_FALSE(fs::exists(png));
}

// export writes the tessellation with its tangent arrays: the VTK XML file names Su, Sv,
// Normals and TCoords.
TEST(CadCli, ExportWritesTheTessellationWithTangents) {
  const fs::path out = dir() / "mould.vtp";
  const Result r = run("export '" + kCad + "mould.step' -o '" + out.string() + "' --style burnished");
  ASSERT_EQ(r.status, 0) << r.err;
  const std::string xml = slurp(out);
  for (const char* name : {"Name=\"Su\"", "Name=\"Sv\"", "Name=\"Normals\"", "Name=\"TCoords\""})
    EXPECT_NE(xml.find(name), std::string::npos) << name;
}

// OpenCASCADE is not linked into the executable: it is opened (with the CAD module) only when
// a CAD file is read (docs/design.md: "load OpenCASCADE only for CAD input").
TEST(CadCli, OpenCascadeIsNotLinkedIntoTheCommand) {
  FILE* p = popen(("ldd '" + std::string(WIREFUR_EXE) + "'").c_str(), "r");
  ASSERT_NE(p, nullptr);
  std::string out;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  pclose(p);
  ASSERT_NE(out.find("libvtkCommonCore"), std::string::npos) << "ldd gave no library list:\n" << out;
  EXPECT_EQ(out.find("libTKernel"), std::string::npos) << out;
  EXPECT_EQ(out.find("WireFurCAD"), std::string::npos) << out;
}

// Edge classes (docs/cad.md): product.step's 72 edges are 16 sharp and 56 smooth (its fillets'
// tangent edges, at 0 degrees), none a seam; `--edges sharp` draws the 16 and no smooth one,
// `--edges boundary` none of them (a closed solid has no border), only the silhouettes. The
// cylinder (a BREP of three faces) hides its seam unless `--seams on`. Bad values: one line,
// exit 2, nothing written.
TEST(CadCli, EdgeClassesAndTheirOptions) {
  const std::string in = kCad + "product.step";
  const json all = renderStats(in, "--style wire", "edges_all");
  ASSERT_TRUE(all.contains("edges_drawn")) << all.dump();
  const json& classes = all["input"]["cad"]["edges_by_class"];
  EXPECT_EQ(classes["sharp"], 16);
  EXPECT_EQ(classes["smooth"], 56);
  EXPECT_EQ(classes["seam"], 0);
  EXPECT_EQ(all["edges_drawn"]["sharp"], 16);
  EXPECT_EQ(all["edges_drawn"]["smooth"], 56);
  EXPECT_GT(all["edges_drawn"]["silhouette"].get<long>(), 0);
  const json sharp = renderStats(in, "--style wire --edges sharp", "edges_sharp");
  EXPECT_EQ(sharp["edges_drawn"]["sharp"], 16);
  EXPECT_EQ(sharp["edges_drawn"]["smooth"], 0);
  EXPECT_LT(sharp["segments"].get<long>(), all["segments"].get<long>());
  // A feature angle above 90 makes the box-like rim's edges smooth too.
  const json wide = renderStats(in, "--style wire --edges sharp --feature-angle 120", "edges_wide");
  EXPECT_EQ(wide["edges_drawn"]["sharp"], 0);
  const json boundary = renderStats(in, "--style wire --edges boundary", "edges_boundary");
  EXPECT_EQ(boundary["edges_drawn"]["sharp"], 0);
  EXPECT_EQ(boundary["edges_drawn"]["smooth"], 0);
  EXPECT_GT(boundary["edges_drawn"]["silhouette"].get<long>(), 0);

  const std::string cyl = std::string(WIREFUR_SOURCE_DIR) + "/tests/apps/cad_regressions/binary_brep_from_BinTools_Write.brep";
  const json noSeam = renderStats(cyl, "--style wire", "edges_cyl");
  EXPECT_EQ(noSeam["input"]["cad"]["edges_by_class"]["seam"], 1);
  EXPECT_EQ(noSeam["edges_drawn"]["seam"], 0);
  EXPECT_EQ(noSeam["edges_drawn"]["sharp"], 2);
  const json seam = renderStats(cyl, "--style wire --seams on", "edges_cyl_seam");
  EXPECT_EQ(seam["edges_drawn"]["seam"], 1);

  for (const char* bad : {"--edges some", "--seams maybe", "--feature-angle 200", "--feature-angle -1", "--feature-angle nan"}) {
    const fs::path png = dir() / "edges_bad.png";
    const Result r = run("render '" + in + "' -o '" + png.string() + "' " + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_EQ(wf::test::lineCount(r.err), 1) << bad << ": " << r.err;
    EXPECT_FALSE(fs::exists(png)) << bad;
  }
}

// The scene key wire.edges: a string or {"mode", "feature_angle", "seams"}; its keys are checked.
TEST(CadCli, EdgeClassesSceneKey) {
  const std::string cyl = std::string(WIREFUR_SOURCE_DIR) + "/tests/apps/cad_regressions/binary_brep_from_BinTools_Write.brep";
  const std::string scene = write("edges_key.json", R"({"objects": [{"file": ")" + cyl + R"(", "surface": false,
    "wire": {"from": "edges", "thickness": 1.5, "units": "pixels", "edges": {"mode": "sharp", "seams": true, "feature_angle": 30}}}]})");
  const json s = renderStats(scene, "", "edges_key");
  EXPECT_EQ(s["edges_drawn"]["seam"], 1);
  EXPECT_EQ(s["edges_drawn"]["sharp"], 2);
  const std::string bad = write("edges_bad_key.json", R"({"objects": [{"file": ")" + cyl + R"(", "surface": false,
    "wire": {"from": "edges", "edges": {"mode": "sharp", "angle": 30}}}]})");
  const Result r = run("render '" + bad + "' -o '" + (dir() / "edges_bad_key.png").string() + "'");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("/objects/0/wire/edges"), std::string::npos) << r.err;
  EXPECT_EQ(wf::test::lineCount(r.err), 1) << r.err;
}

// export --visibility: every wire-frame cut into pieces each wholly seen or hidden from the
// framed camera, with cell arrays EdgeClass (the piece's edge's class) and Visible; both answers
// occur on product.step seen from above (the tray's far walls hide parts of its near rim's
// inner edges... and its underside edges); the pieces' lengths add up to the edges' lengths
// without --visibility (1e-9 relative). Without --visibility there is no Visible array.
TEST(CadCli, ExportCarriesEdgeClassAndVisibility) {
  auto read = [](const fs::path& p) {
    vtkNew<vtkXMLPolyDataReader> r;
    r->SetFileName(p.string().c_str());
    r->Update();
    vtkSmartPointer<vtkPolyData> pd = r->GetOutput();
    return pd;
  };
  auto lineLength = [](vtkPolyData* pd, int visible) {
    double total = 0;
    vtkDataArray* vis = pd->GetCellData()->GetArray("Visible");
    vtkNew<vtkIdList> ids;
    vtkCellArray* lines = pd->GetLines();
    vtkIdType c = 0;
    for (lines->InitTraversal(); lines->GetNextCell(ids); ++c) {
      if (visible >= 0 && (!vis || int(vis->GetTuple1(c)) != visible)) continue;
      for (vtkIdType k = 1; k < ids->GetNumberOfIds(); ++k) {
        double a[3], b[3];
        pd->GetPoint(ids->GetId(k - 1), a);
        pd->GetPoint(ids->GetId(k), b);
        total += std::sqrt(vtkMath::Distance2BetweenPoints(a, b));
      }
    }
    return total;
  };
  const fs::path plain = dir() / "edges_plain.vtp", split = dir() / "edges_split.vtp";
  const std::string in = kCad + "product.step";
  Result r = run("export '" + in + "' -o '" + plain.string() + "' --style wire --silhouettes off");
  ASSERT_EQ(r.status, 0) << r.err;
  r = run("export '" + in + "' -o '" + split.string() + "' --style wire --silhouettes off --visibility --quiet");
  ASSERT_EQ(r.status, 0) << r.err;
  const vtkSmartPointer<vtkPolyData> a = read(plain), b = read(split);
  EXPECT_EQ(a->GetCellData()->GetArray("Visible"), nullptr);
  ASSERT_NE(b->GetCellData()->GetArray("Visible"), nullptr);
  ASSERT_NE(b->GetCellData()->GetArray("EdgeClass"), nullptr);
  EXPECT_EQ(a->GetNumberOfPolys(), 0) << "the hold-out faces are not written";
  EXPECT_EQ(b->GetNumberOfPolys(), 0);
  EXPECT_EQ(a->GetNumberOfLines(), 72);
  EXPECT_GT(b->GetNumberOfLines(), 72);
  std::set<int> seen, classes;
  for (vtkIdType c = 0; c < b->GetNumberOfLines(); ++c) {
    seen.insert(int(b->GetCellData()->GetArray("Visible")->GetTuple1(c)));
    classes.insert(int(b->GetCellData()->GetArray("EdgeClass")->GetTuple1(c)));
  }
  EXPECT_EQ(seen, (std::set<int>{0, 1}));
  EXPECT_EQ(classes, (std::set<int>{1, 2}));
  const double whole = lineLength(a, -1), seenLength = lineLength(b, 1), hiddenLength = lineLength(b, 0);
  EXPECT_NEAR(seenLength + hiddenLength, whole, 1e-9 * whole);
  EXPECT_GT(seenLength, 0.2 * whole);
  EXPECT_GT(hiddenLength, 0.2 * whole);
}

// Brushed steel on a CAD part (docs/cad.md "Brushed steel"): grooves by default in the burnished
// style, at 10 a millimetre across each face's grain, the grain along each face's longer extent
// (product.step: 35 faces laid out, some along u, some along v). The grooves do not move with the
// mesh: rendered at deflections 1e-3 and 3e-4 (640 x 480) the images differ by no more with
// grooves than without them (RMS, 5e-4 of slack: what differs is the tessellation's shading, 2e-3
// here), while the grooves themselves change the image by more than 5e-3. --grooves-per-mm 0 and
// --grain circular are taken; bad values are one line, exit 2 (an axis needs circular or radial grain,
// as the scene file's burnish.axis does).
TEST(CadCli, BrushedSteelGroovesFollowThePartNotTheMesh) {
  const std::string in = kCad + "product.step";
  const json s = renderStats(in, "--style burnished", "steel_stats");
  ASSERT_TRUE(s.contains("burnish")) << s.dump();
  EXPECT_EQ(s["burnish"]["grooves_per_unit"], 10.0);
  EXPECT_EQ(s["burnish"]["faces"]["laid_out"], 35);
  EXPECT_GT(s["burnish"]["faces"]["along_u"].get<long>(), 0);
  EXPECT_GT(s["burnish"]["faces"]["along_v"].get<long>(), 0);
  auto render = [&](const std::string& extra, const std::string& tag) {
    const fs::path png = dir() / (tag + ".png");
    const Result r = run("render '" + in + "' -o '" + png.string() + "' --size 640x480 --style burnished --quiet " + extra);
    EXPECT_EQ(r.status, 0) << r.err;
    vtkNew<vtkPNGReader> reader;
    reader->SetFileName(png.string().c_str());
    reader->Update();
    vtkSmartPointer<vtkImageData> image = reader->GetOutput();
    return image;
  };
  auto rms = [](vtkImageData* a, vtkImageData* b) {
    vtkDataArray* x = a->GetPointData()->GetScalars();
    vtkDataArray* y = b->GetPointData()->GetScalars();
    double sum = 0;
    const vtkIdType n = x->GetNumberOfValues();
    for (vtkIdType i = 0; i < n; ++i) {
      const double d = (x->GetVariantValue(i).ToDouble() - y->GetVariantValue(i).ToDouble()) / 255.0;
      sum += d * d;
    }
    return std::sqrt(sum / double(n));
  };
  const auto g3 = render("--deflection 1e-3", "steel_g3"), g4 = render("--deflection 3e-4", "steel_g4");
  const auto n3 = render("--deflection 1e-3 --grooves-per-mm 0", "steel_n3"), n4 = render("--deflection 3e-4 --grooves-per-mm 0", "steel_n4");
  const double withGrooves = rms(g3, g4), without = rms(n3, n4), grooves = rms(g3, n3);
  EXPECT_LT(withGrooves, without + 5e-4) << withGrooves << " " << without;
  EXPECT_GT(grooves, 5e-3);
  const json turned = renderStats(in, "--style burnished --grain circular --grain-axis 0,0,0,0,0,1", "steel_circular");
  EXPECT_FALSE(turned["burnish"].contains("faces"));  // circular grain: no per-face layout
  for (const char* bad : {"--grain diagonal", "--grain-axis 0,0,0,0,0,0", "--grain-axis 1,2,3", "--grooves-per-mm -1",
                          "--grain-axis 0,0,0,0,0,1", "--grain u --grain-axis 0,0,0,0,0,1", "--grain-axis 0,0,0,0,0,1 --grain longer"}) {
    const fs::path png = dir() / "steel_bad.png";
    const Result r = run("render '" + in + "' -o '" + png.string() + "' --style burnished " + bad);
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_EQ(wf::test::lineCount(r.err), 1) << bad << ": " << r.err;
    EXPECT_FALSE(fs::exists(png)) << bad;
  }
}

// Stopped with SIGTERM while its worker meshes (the mould at 1e-6 of its size, which takes
// minutes): the command dies of the signal, and its worker and the worker's folder under TMPDIR
// go with it at once.
TEST(CadCli, StoppedWhileReadingLeavesNoWorkerOrFolder) {
  const fs::path tmp = wf::test::scratchDir("wirefur-cad-stopped");
  const char* old = std::getenv("TMPDIR");
  const std::string saved = old ? old : "";
  setenv("TMPDIR", tmp.c_str(), 1);
  const pid_t pid = wf::test::spawnWirefur({"render", kCad + "mould.step", "-o", (tmp / "x.png").string(), "--deflection", "0.000001"});
  if (old) setenv("TMPDIR", saved.c_str(), 1);
  else unsetenv("TMPDIR");
  ASSERT_GT(pid, 0);
  wf::test::ProcessGuard guard{pid};
  auto folders = [&] {
    int n = 0;
    for (const auto& e : fs::directory_iterator(tmp)) n += e.path().filename().string().rfind("wirefur-read-", 0) == 0;
    return n;
  };
  // The worker's folder appears under our TMPDIR (not /tmp); then the worker runs a while.
  bool seen = false;
  for (int i = 0; i < 3000 && !seen; ++i) {
    seen = folders() > 0;
    if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  ASSERT_TRUE(seen) << "no wirefur-read-* folder under TMPDIR";
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  kill(pid, SIGTERM);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  guard.pid = -1;
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << status;
  EXPECT_EQ(folders(), 0);
  // No process is left reading the file (its command line names it).
  int workers = 0;
  for (const auto& e : fs::directory_iterator("/proc")) {
    std::ifstream f(e.path() / "cmdline", std::ios::binary);
    std::string cmd((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
    workers += cmd.find(std::string("cad-worker") + '\0' + kCad + "mould.step") != std::string::npos &&
               cmd.find(tmp.string()) != std::string::npos;
  }
  EXPECT_EQ(workers, 0);
  EXPECT_FALSE(fs::exists(tmp / "x.png"));
}
