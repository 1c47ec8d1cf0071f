#include "mesh_io.h"

#include "cli.h"
#include "reader_worker.h"
#include "safe_files.h"

#include "core/worker_process.h"

#include <vtkCellArray.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkIdList.h>
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkOBJReader.h>
#include <vtkPLYReader.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataNormals.h>
#include <vtkAlgorithm.h>
#include <vtkPolyDataReader.h>
#include <vtkSTLReader.h>
#include <vtkSmartPointer.h>
#include <vtkTriangleFilter.h>
#include <vtkCellData.h>
#include <vtkDataSetAttributes.h>
#include <vtkAbstractArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkXMLPolyDataReader.h>
#include <vtkXMLPolyDataWriter.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <sstream>
#include <vector>
#include <string>
#include <string_view>

namespace wfapp {

namespace {

std::string extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}

// Collects the first error VTK reports instead of letting it print a multi-line message.
class ErrorCatcher : public vtkCommand {
 public:
  static ErrorCatcher* New() { return new ErrorCatcher; }
  void Execute(vtkObject*, unsigned long, void* data) override {
    if (message.empty() && data) {
      message = static_cast<const char*>(data);
      // Keep the last line, which is the reader's own words.
      while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
      const size_t nl = message.rfind('\n');
      if (nl != std::string::npos) message = message.substr(nl + 1);
      // Drop VTK's "vtkSomeReader (0x...): " prefix: the reader's words are what matter.
      const size_t tag = message.find("): ");
      if (message.rfind("vtk", 0) == 0 && tag != std::string::npos && tag < 64) message = message.substr(tag + 3);
    }
  }
  std::string message;
};

// The pre-checks below (checkPly, checkStl, checkVtp, checkObj) run before VTK's readers, inside
// the mesh worker (apps/reader_worker.h) when the command reads. The worker already contains what
// they guard against (a crash, a hang, an allocation without end becomes one line); they stay
// because their words are better than the worker's: "FILE:13: face 0: index 5 out of range 0..2"
// or "NumberOfPoints 9e14 is not a count" at once, against "VTK's reader crashed reading this
// file" or an out-of-memory after seconds of allocating. A file they do not foresee is the
// worker's (tests/apps/mesh_regressions/vtk_field_without_name.vtk).
//
// A file read front to back through one buffer, as lines or as bytes: the pre-checks below walk
// files of hundreds of MB in one pass and bounded memory (a line is kept only up to a cap).
class FileCursor {
 public:
  explicit FileCursor(const std::string& path) : in_(path, std::ios::binary), buf_(std::size_t(1) << 20) {
    std::error_code ec;
    size_ = std::filesystem::file_size(path, ec);
    if (ec) size_ = 0;
  }
  std::uint64_t offset() const { return base_ + pos_; }
  std::uint64_t remaining() const { return size_ > offset() ? size_ - offset() : 0; }
  // One line without its '\n': at most `cap` characters are kept in `out`, `length` is the whole
  // length, `terminated` whether a '\n' ended it. False at the end of the file with nothing read.
  bool line(std::string& out, std::size_t cap, std::uint64_t& length, bool& terminated) {
    out.clear();
    length = 0;
    terminated = false;
    bool any = false;
    for (;;) {
      if (pos_ == end_ && !fill()) return any;
      any = true;
      const char* start = buf_.data() + pos_;
      const std::size_t avail = end_ - pos_;
      const char* nl = static_cast<const char*>(std::memchr(start, '\n', avail));
      const std::size_t n = nl ? std::size_t(nl - start) : avail;
      if (out.size() < cap) out.append(start, std::min(n, cap - out.size()));
      length += n;
      pos_ += n;
      if (nl) {
        ++pos_;
        terminated = true;
        return true;
      }
    }
  }
  bool read(void* dst, std::size_t n) {
    char* d = static_cast<char*>(dst);
    while (n > 0) {
      if (pos_ == end_ && !fill()) return false;
      const std::size_t k = std::min(n, end_ - pos_);
      std::memcpy(d, buf_.data() + pos_, k);
      pos_ += k;
      d += k;
      n -= k;
    }
    return true;
  }
  bool skip(std::uint64_t n) {
    if (n > remaining()) return false;
    const std::uint64_t inBuffer = end_ - pos_;
    if (n <= inBuffer) {
      pos_ += std::size_t(n);
      return true;
    }
    const std::uint64_t target = offset() + n;
    in_.clear();
    in_.seekg(std::streamoff(target));
    base_ = target;
    pos_ = end_ = 0;
    return bool(in_);
  }

 private:
  bool fill() {
    base_ += end_;
    pos_ = end_ = 0;
    if (!in_) return false;
    in_.read(buf_.data(), std::streamsize(buf_.size()));
    end_ = std::size_t(in_.gcount());
    return end_ > 0;
  }
  std::ifstream in_;
  std::vector<char> buf_;
  std::size_t pos_ = 0, end_ = 0;
  std::uint64_t base_ = 0, size_ = 0;
};

// strtol's reading of a number's start (white space, a sign, decimal digits), saturating far
// outside int; `digits` is false when there are none (atoi would give 0).
long long leadingInteger(std::string_view s, bool& digits) {
  std::size_t i = 0;
  while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  bool negative = false;
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
  long long v = 0;
  digits = false;
  for (; i < s.size() && s[i] >= '0' && s[i] <= '9'; ++i) {
    digits = true;
    if (v < 1000000000000000LL) v = v * 10 + (s[i] - '0');
  }
  return negative ? -v : v;
}

// ---- PLY: what VTK 9.1's vtkPLYReader (vtkPLY.cxx) does with a file, and where it goes wrong ----
// The reader trusts the file: it reads the header's elements in order but consumes data only for
// "vertex" and "face" (other elements are not skipped), reads each ASCII record as one line of at
// most 4095 characters split at spaces, indexes that line's words without counting them, reads
// binary items without checking for the end of the file, allocates a list from its count (a
// negative one included) and builds each face from its vertex indices with vtkCell::Initialize,
// which reads the points by those indices unchecked. A record it cannot read leaves the face it
// fills uninitialised (a wild free() follows). So before VTK sees a file, its header and the
// records VTK will read are walked here the way VTK walks them, in one pass.

enum class PlyType { Bad, I8, U8, I16, U16, I32, U32, F32, F64 };

PlyType plyType(std::string_view t) {
  if (t == "char" || t == "int8") return PlyType::I8;
  if (t == "uchar" || t == "uint8") return PlyType::U8;
  if (t == "short" || t == "int16") return PlyType::I16;
  if (t == "ushort" || t == "uint16") return PlyType::U16;
  if (t == "int" || t == "int32") return PlyType::I32;
  if (t == "uint" || t == "uint32") return PlyType::U32;
  if (t == "float" || t == "float32") return PlyType::F32;
  if (t == "double" || t == "float64") return PlyType::F64;
  return PlyType::Bad;
}

int plySize(PlyType t) {
  switch (t) {
    case PlyType::I8: case PlyType::U8: return 1;
    case PlyType::I16: case PlyType::U16: return 2;
    case PlyType::I32: case PlyType::U32: case PlyType::F32: return 4;
    case PlyType::F64: return 8;
    default: return 0;
  }
}

struct PlyProp {
  std::string name;
  bool list = false;
  PlyType count = PlyType::Bad, type = PlyType::Bad;
};

struct PlyElement {
  std::string name;
  std::uint64_t count = 0;
  std::vector<PlyProp> props;
  bool has(const char* n, bool list) const {
    return std::any_of(props.begin(), props.end(), [&](const PlyProp& p) { return p.name == n && p.list == list; });
  }
};

constexpr std::size_t kPlyLineCap = 4095;  // vtkPLY::get_words: getline into char[4096]

// vtkPLY::get_words on one line (at most kPlyLineCap characters, without its '\n'): the text up
// to a NUL, "vertex_index" rewritten as "vertex_indices" (and the line cut there), character
// 4094 made a space, tabs and CRs as spaces, words split at spaces. The words view `s`. False
// where the rewrite would run past VTK's buffer.
bool plyWords(std::string& s, std::vector<std::string_view>& words) {
  words.clear();
  if (s.size() >= 4000) {  // near VTK's buffer: do exactly what it does to char[4096]
    char str[4096] = {};
    std::memcpy(str, s.data(), s.size());
    if (char* pos = std::strstr(str, "vertex_index")) {
      if (pos - str + 15 > 4094) return false;
      std::strcpy(pos, "vertex_indices");
    }
    str[4094] = ' ';
    str[4095] = '\0';
    s.assign(str);
  } else {
    if (const std::size_t nul = s.find('\0'); nul != std::string::npos) s.resize(nul);
    if (const std::size_t pos = s.find("vertex_index"); pos != std::string::npos) s.replace(pos, std::string::npos, "vertex_indices");
  }
  for (char& c : s)
    if (c == '\t' || c == '\r') c = ' ';
  for (std::size_t i = 0; i < s.size();) {
    while (i < s.size() && s[i] == ' ') ++i;
    const std::size_t b = i;
    while (i < s.size() && s[i] != ' ') ++i;
    if (i > b) words.emplace_back(s.data() + b, i - b);
  }
  return true;
}

// The int VTK takes from an ASCII word as a list count or an index (atoi, strtoul or atof, then
// int); false for a value it cannot represent as one (NaN, outside int).
bool plyAsciiInt(std::string_view w, PlyType t, long long& v) {
  if (t == PlyType::F32 || t == PlyType::F64) {
    const std::string tmp(w);
    const double d = std::atof(tmp.c_str());
    if (!std::isfinite(d) || d <= -2147483649.0 || d >= 2147483648.0) return false;
    v = static_cast<long long>(d);
    return true;
  }
  bool digits = false;
  v = leadingInteger(w, digits);
  return v >= -2147483648LL && v <= 2147483647LL;
}

// The same for a binary item (`b` holds plySize(t) bytes in the file's byte order).
bool plyBinaryInt(const unsigned char* b, PlyType t, bool bigEndian, long long& v) {
  const int n = plySize(t);
  std::uint64_t u = 0;
  for (int k = 0; k < n; ++k) u |= std::uint64_t(b[bigEndian ? k : n - 1 - k]) << (8 * (n - 1 - k));
  switch (t) {
    case PlyType::I8: v = static_cast<std::int8_t>(u); return true;
    case PlyType::U8: v = static_cast<long long>(u); return true;
    case PlyType::I16: v = static_cast<std::int16_t>(u); return true;
    case PlyType::U16: v = static_cast<long long>(u); return true;
    case PlyType::I32: v = static_cast<std::int32_t>(u); return true;
    case PlyType::U32: v = static_cast<long long>(u); return v <= 2147483647LL;  // VTK's int turns it negative
    case PlyType::F32: case PlyType::F64: {
      double d;
      if (t == PlyType::F32) {
        float f;
        const std::uint32_t u32 = std::uint32_t(u);
        std::memcpy(&f, &u32, 4);
        d = f;
      } else {
        std::memcpy(&d, &u, 8);
      }
      if (!std::isfinite(d) || d <= -2147483649.0 || d >= 2147483648.0) return false;
      v = static_cast<long long>(d);
      return true;
    }
    default: return false;
  }
}

void checkPly(const std::string& path) {
  FileCursor in(path);
  std::string line;
  std::uint64_t length = 0;
  bool terminated = false;
  std::vector<std::string_view> w;
  std::uint64_t lineNo = 1;
  auto at = [&]() { return path + ":" + std::to_string(lineNo) + ": "; };
  if (!in.line(line, kPlyLineCap + 1, length, terminated) || length > kPlyLineCap || !plyWords(line, w) || w.empty() || w[0] != "ply")
    throw UsageError(path + ": not a PLY file (no 'ply' magic)");
  if (!terminated) throw UsageError(path + ": PLY header has no end_header");
  std::string format;
  std::vector<PlyElement> elements;
  bool ended = false;
  while (in.line(line, kPlyLineCap + 1, length, terminated)) {
    ++lineNo;
    if (length > kPlyLineCap) throw UsageError(at() + "PLY header line longer than 4095 characters (VTK's reader's limit)");
    // VTK's reader ends the header at a line without a newline or without words and reads on.
    if (!terminated) break;
    if (!plyWords(line, w)) throw UsageError(at() + "PLY header: misplaced 'vertex_index'");
    if (w.empty()) throw UsageError(at() + "PLY header: empty line");
    if (w[0] == "format") {
      if (w.size() != 3) throw UsageError(at() + "PLY header: bad format line");
      format = std::string(w[1]);
    } else if (w[0] == "element") {
      bool digits = false;
      const long long n = w.size() >= 3 ? leadingInteger(w[2], digits) : -1;
      if (w.size() < 3 || !digits || n < 0 || n > 2000000000LL) throw UsageError(at() + "PLY header: bad element line");
      PlyElement e;
      e.name = std::string(w[1]);
      e.count = std::uint64_t(n);
      if ((e.name == "vertex" || e.name == "face") &&
          std::any_of(elements.begin(), elements.end(), [&](const PlyElement& o) { return o.name == e.name; }))
        throw UsageError(at() + "PLY header: a second '" + e.name + "' element");
      elements.push_back(std::move(e));
    } else if (w[0] == "property") {
      if (elements.empty()) throw UsageError(at() + "PLY header: property before any element");
      PlyProp p;
      if (w.size() >= 2 && w[1] == "list") {
        if (w.size() < 5) throw UsageError(at() + "PLY header: bad list property line");
        p.list = true;
        p.count = plyType(w[2]);
        p.type = plyType(w[3]);
        p.name = std::string(w[4]);
        if (p.count == PlyType::Bad) throw UsageError(at() + "PLY header: unknown property type '" + std::string(w[2]) + "'");
        if (p.type == PlyType::Bad) throw UsageError(at() + "PLY header: unknown property type '" + std::string(w[3]) + "'");
      } else {
        if (w.size() < 3) throw UsageError(at() + "PLY header: bad property line");
        p.type = plyType(w[1]);
        p.name = std::string(w[2]);
        if (p.type == PlyType::Bad) throw UsageError(at() + "PLY header: unknown property type '" + std::string(w[1]) + "'");
      }
      elements.back().props.push_back(std::move(p));
    } else if (w[0] == "end_header") {
      ended = true;
      break;
    }
  }
  if (!ended) throw UsageError(path + ": PLY header has no end_header");
  // VTK's reader leaves the property list of an element without properties unset, and frees it
  // when it closes the file (a crash found by fuzzing).
  for (const PlyElement& e : elements)
    if (e.props.empty()) throw UsageError(path + ": PLY header: element '" + e.name + "' has no properties");
  const bool binary = format == "binary_little_endian" || format == "binary_big_endian";
  if (!binary && format != "ascii") throw UsageError(path + ": PLY header: unknown format '" + format + "'");
  const bool bigEndian = format == "binary_big_endian";
  // Without a vertex element of scalar x, y and z VTK's reader says "Cannot read geometry",
  // closes the file and goes on reading from it (a crash found by fuzzing).
  const auto vertex = std::find_if(elements.begin(), elements.end(), [](const PlyElement& e) { return e.name == "vertex"; });
  if (vertex == elements.end() || !vertex->has("x", false) || !vertex->has("y", false) || !vertex->has("z", false))
    throw UsageError(path + ": PLY header: no vertex element with x, y and z properties");
  // The properties VTK asks for are stored into its own structs as the kind it expects: a list
  // where it expects a number writes a pointer past them, a number where it expects a list
  // leaves the list pointer unset.
  const auto face = std::find_if(elements.begin(), elements.end(), [](const PlyElement& e) { return e.name == "face"; });
  for (const PlyElement& e : elements) {
    if (e.name != "vertex" && e.name != "face") continue;
    for (const PlyProp& p : e.props) {
      static const std::vector<std::string> vertexScalars = {"x", "y", "z", "u", "v", "texture_u", "texture_v", "nx", "ny", "nz",
                                                             "red", "green", "blue", "alpha", "diffuse_red", "diffuse_green", "diffuse_blue"};
      static const std::vector<std::string> faceScalars = {"intensity", "red", "green", "blue", "alpha"};
      const auto& scalars = e.name == "vertex" ? vertexScalars : faceScalars;
      const bool wantList = e.name == "face" && (p.name == "vertex_indices" || p.name == "texcoord");
      const bool wantScalar = std::find(scalars.begin(), scalars.end(), p.name) != scalars.end();
      if ((wantList && !p.list) || (wantScalar && p.list))
        throw UsageError(path + ": PLY header: " + e.name + " property '" + p.name + "' must be " + (wantList ? "a list" : "a number"));
    }
  }
  if (face != elements.end() && face->count > 0) {
    if (!face->has("vertex_indices", true))
      throw UsageError(path + ": PLY header: the face element has no 'vertex_indices' list");
    if (face < vertex) throw UsageError(path + ": PLY header: the face element comes before the vertex element");
  }
  if (binary) {
    // Every element's data is there in a well-formed file (a list counts its length field only).
    std::uint64_t need = 0;
    for (const PlyElement& e : elements) {
      std::uint64_t fixed = 0;
      for (const PlyProp& p : e.props) fixed += std::uint64_t(plySize(p.list ? p.count : p.type));
      need += e.count * fixed;
    }
    if (in.remaining() < need)
      throw UsageError(path + ": PLY body is " + std::to_string(in.remaining()) + " bytes, the header declares at least " + std::to_string(need));
  }

  // The records VTK reads: the vertex and face elements, in the header's order, one after the
  // other from the end of the header.
  const std::uint64_t vertexCount = vertex->count;
  const std::string range = vertexCount == 0 ? std::string(" out of range (no vertices)") : " out of range 0.." + std::to_string(vertexCount - 1);
  unsigned char item[8];
  for (const PlyElement& e : elements) {
    if (e.name != "vertex" && e.name != "face") continue;
    const bool isFace = e.name == "face";
    const bool allScalars = std::none_of(e.props.begin(), e.props.end(), [](const PlyProp& p) { return p.list; });
    if (binary && allScalars) {
      std::uint64_t record = 0;
      for (const PlyProp& p : e.props) record += std::uint64_t(plySize(p.type));
      if (!in.skip(record * e.count))
        throw UsageError(path + ": PLY body ends inside the " + e.name + " data (" + std::to_string(e.count) + " of " +
                         std::to_string(record) + " bytes each declared)");
      continue;
    }
    for (std::uint64_t r = 0; r < e.count; ++r) {
      auto what = [&]() { return e.name + " " + std::to_string(r); };
      if (binary) {
        auto truncated = [&]() {
          return UsageError(path + ": PLY body ends inside " + what() + " (the header declares " + std::to_string(e.count) + ")");
        };
        for (const PlyProp& p : e.props) {
          if (!p.list) {
            if (!in.skip(std::uint64_t(plySize(p.type)))) throw truncated();
            continue;
          }
          long long n = 0;
          if (!in.read(item, std::size_t(plySize(p.count)))) throw truncated();
          if (!plyBinaryInt(item, p.count, bigEndian, n) || n < 0)
            throw UsageError(path + ": " + what() + ": list '" + p.name + "' has a bad length");
          const int size = plySize(p.type);
          if (std::uint64_t(n) * std::uint64_t(size) > in.remaining()) throw truncated();
          if (isFace && p.name == "vertex_indices") {
            for (long long k = 0; k < n; ++k) {
              long long index = -1;
              in.read(item, std::size_t(size));
              const bool isInt = plyBinaryInt(item, p.type, bigEndian, index);
              if (!isInt || index < 0 || std::uint64_t(index) >= vertexCount)
                throw UsageError(path + ": " + what() + ": index " +
                                 (isInt || p.type == PlyType::U32 ? std::to_string(index) : std::string("(not a number in int range)")) + range);
            }
          } else if (!in.skip(std::uint64_t(n) * std::uint64_t(size))) {
            throw truncated();
          }
        }
        continue;
      }
      // ASCII: one line per record, read as get_words reads it.
      ++lineNo;
      if (!in.line(line, kPlyLineCap + 1, length, terminated))
        throw UsageError(path + ": PLY body ends before " + std::to_string(e.count) + " " + e.name + " lines");
      if (length > kPlyLineCap) throw UsageError(at() + "PLY line longer than 4095 characters (VTK's reader's limit)");
      if (!terminated) throw UsageError(at() + "PLY " + e.name + " line has no newline at the end of the file");
      if (!plyWords(line, w)) throw UsageError(at() + "PLY " + e.name + " line: misplaced 'vertex_index'");
      std::size_t next = 0;
      auto tooFew = [&]() { return UsageError(at() + "PLY " + e.name + " line has too few values"); };
      for (const PlyProp& p : e.props) {
        if (!p.list) {
          if (next++ >= w.size()) throw tooFew();
          continue;
        }
        if (next >= w.size()) throw tooFew();
        long long n = 0;
        if (!plyAsciiInt(w[next], p.count, n) || n < 0) throw UsageError(at() + what() + ": list '" + p.name + "' has a bad length");
        ++next;
        if (std::uint64_t(n) > w.size() - next) throw tooFew();
        if (isFace && p.name == "vertex_indices")
          for (long long k = 0; k < n; ++k) {
            long long index = -1;
            if (!plyAsciiInt(w[next + std::size_t(k)], p.type, index) || index < 0 || std::uint64_t(index) >= vertexCount)
              throw UsageError(at() + what() + ": index " + std::string(w[next + std::size_t(k)]) + range);
          }
        next += std::size_t(n);
      }
    }
  }
}

// A binary STL is 84 bytes and 50 per triangle; VTK reads a truncated one without a word.
void checkStl(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[84] = {};
  in.read(head, 84);
  const std::uint64_t size = std::filesystem::file_size(path);
  if (in.gcount() == 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, head + 80, 4);
    if (84 + 50 * std::uint64_t(n) == size) return;  // a well-formed binary STL (even if it says "solid")
  }
  if (std::string(head, std::min<std::streamsize>(in.gcount(), 5)) == "solid") return;  // ASCII: VTK parses it
  if (in.gcount() < 84) throw UsageError(path + ": too short for an STL file");
  std::uint32_t n = 0;
  std::memcpy(&n, head + 80, 4);
  throw UsageError(path + ": binary STL declares " + std::to_string(n) + " triangles (" + std::to_string(84 + 50 * std::uint64_t(n)) +
                   " bytes) but the file has " + std::to_string(size));
}

// ---- OBJ: what VTK 9.1's vtkOBJReader does with a file, and where it goes wrong ----
// The reader resolves the 1-based (or, negative, relative to the count so far) indices of "f",
// "l" and "p" without a range check: it looks texture coordinates up at once in the list of all
// "vt" lines and writes into an array of that size, and, where a file's faces index texture
// coordinates or normals apart from their vertices, copies points, normals and texture
// coordinates by those indices (SEGV, heap corruption: bad-free, alloc-dealloc mismatch). It
// reads lines with fgets into 256 KiB and a "usemtl" name with sscanf("%s") into char[100].
// Its index parsing is sscanf's ("%d/%d/%d", then "%d//%d", "%d/%d", "%d", at each word start),
// redone here so that the indices checked are the ones VTK will use.

constexpr std::size_t kObjLineCap = 262142;  // fgets into char[262144], with the '\n'

// sscanf(p, fmt) for the formats above: "%d" (white space, a sign, digits) and a literal '/'.
// Returns how many numbers it converted.
int objScan(const char* p, const char* end, const char* fmt, long long out[3]) {
  int n = 0;
  for (; *fmt; ++fmt) {
    if (*fmt == '/') {
      if (p == end || *p != '/') return n;
      ++p;
      continue;
    }
    ++fmt;  // "%d"
    while (p != end && std::isspace(static_cast<unsigned char>(*p))) ++p;
    const char* q = p;
    bool negative = false;
    if (q != end && (*q == '+' || *q == '-')) negative = *q++ == '-';
    long long v = 0;
    const char* digits = q;
    for (; q != end && *q >= '0' && *q <= '9'; ++q)
      if (v < 1000000000000LL) v = v * 10 + (*q - '0');
    if (q == digits) return n;
    out[n++] = negative ? -v : v;
    p = q;
  }
  return n;
}

// VTK's XML reader sizes its arrays from the Piece's NumberOf... attributes before it reads a
// value: a count no mesh WireFur can draw is refused here (fuzzing: NumberOfPoints 9e14 made it
// ask for terabytes). Only the counts are scanned; VTK parses the file.
void checkVtp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(1 << 16, '\0');
  in.read(head.data(), std::streamsize(head.size()));
  head.resize(size_t(in.gcount()));
  constexpr double kMaxCount = 2147483647.0;  // VTK ids beyond int32 are not a mesh we can draw
  for (const char* key : {"NumberOfPoints=\"", "NumberOfVerts=\"", "NumberOfLines=\"", "NumberOfStrips=\"",
                          "NumberOfPolys=\""}) {
    for (size_t at = head.find(key); at != std::string::npos; at = head.find(key, at + 1)) {
      const size_t v = at + std::strlen(key);
      const size_t end = head.find('"', v);
      if (end == std::string::npos) break;
      // Only a plain integer is judged here (and quoted back: digits only, one line); anything
      // else is VTK's to refuse as it parses.
      std::string value = head.substr(v, end - v);
      const size_t first = value.find_first_not_of(" \t");
      value = first == std::string::npos ? std::string() : value.substr(first);
      const size_t digits = value.find_first_not_of("0123456789", value.rfind('-', 0) == 0 ? 1 : 0);
      if (value.empty() || value == "-" || digits != std::string::npos || value.size() > 40) continue;
      const double n = std::strtod(value.c_str(), nullptr);
      if (!(n >= 0) || n > kMaxCount)
        throw UsageError(path + ": " + std::string(key, std::strlen(key) - 2) + " \"" + value +
                         "\" is not a count WireFur can read (0 ... 2147483647)");
    }
  }
}

void checkObj(const std::string& path) {
  FileCursor in(path);
  std::string line;
  std::uint64_t length = 0, lineNo = 0;
  bool terminated = false;
  auto at = [&]() { return path + ":" + std::to_string(lineNo) + ": "; };
  // What a file refers to: its vertices, texture coordinates and normals. Negative indices are
  // checked against the count so far as they come; positive ones against the whole file's count
  // at the end (VTK resolves them after reading), by the largest one and where it was.
  struct Kind {
    const char* name;
    long long current = 0, largest = 0;
    std::uint64_t largestLine = 0;
    std::string largestCommand;
  };
  Kind vertices{"vertex", 0, 0, 0, {}}, tcoords{"texture coordinate", 0, 0, 0, {}}, normals{"normal", 0, 0, 0, {}};
  long long tcoordLines = 0;  // VTK's first pass counts "vt" on every line, continuations included
  auto firstWord = [](const std::string& s, std::size_t from, std::size_t& b, std::size_t& e) {
    b = from;
    while (b < s.size() && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
    e = b;
    while (e < s.size() && !std::isspace(static_cast<unsigned char>(s[e]))) ++e;
  };
  // One physical line, with the checks VTK's first pass needs.
  auto nextLine = [&]() -> bool {
    if (!in.line(line, kObjLineCap + 1, length, terminated)) return false;
    ++lineNo;
    if (length > kObjLineCap) throw UsageError(at() + "line longer than 262142 characters (VTK's OBJ reader's limit)");
    if (line.find('\0') != std::string::npos) throw UsageError(at() + "NUL byte in a text OBJ file");
    std::size_t b, e;
    firstWord(line, 0, b, e);
    const std::string_view cmd(line.data() + b, e - b);
    if (cmd == "vt") ++tcoordLines;
    if (cmd == "usemtl") {
      std::size_t nb, ne;
      firstWord(line, e, nb, ne);
      if (ne - nb >= 100) throw UsageError(at() + "material name longer than 99 characters (VTK's OBJ reader's limit)");
    }
    return true;
  };
  auto use = [&](Kind& k, long long i, const std::string& cmd) {
    if (i < 0) {
      if (-i > k.current)
        throw UsageError(at() + cmd + ": relative " + k.name + " index " + std::to_string(i) + " reaches before the first (" +
                         std::to_string(k.current) + " so far)");
    } else if (i == 0) {
      throw UsageError(at() + cmd + ": " + k.name + " index 0 (OBJ indices start at 1)");
    } else if (i > k.largest) {
      k.largest = i;
      k.largestLine = lineNo;
      k.largestCommand = cmd;
    }
  };
  while (nextLine()) {
    std::size_t b, e;
    firstWord(line, 0, b, e);
    const std::string cmd = line.substr(b, e - b);
    if (cmd == "v") {
      // VTK's reader reads a vertex coordinate it cannot parse ("nan", "inf", "1.5x") as some
      // finite number without a word: the geometry would be silently wrong. Every "v" line must
      // have three finite numbers.
      std::istringstream ws(line.substr(e));
      for (int k = 0; k < 3; ++k) {
        std::string tok;
        if (!(ws >> tok)) throw UsageError(at() + "vertex with fewer than 3 coordinates");
        char* stop = nullptr;
        const double x = std::strtod(tok.c_str(), &stop);
        if (stop == tok.c_str() || *stop != '\0' || !std::isfinite(x))
          throw UsageError(at() + "vertex coordinate '" + tok + "' is not a finite number");
      }
      ++vertices.current;
    } else if (cmd == "vt") {
      ++tcoords.current;
    } else if (cmd == "vn") {
      ++normals.current;
    } else if (cmd == "f" || cmd == "l" || cmd == "p") {
      // VTK cuts the command at the white space after it and reads from the next character.
      std::size_t i = e < line.size() ? e + 1 : e;
      for (;;) {
        while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
        if (i >= line.size()) break;
        const char* p = line.data() + i;
        const char* end = line.data() + line.size();
        long long v[3];
        if (cmd == "f" && objScan(p, end, "%d/%d/%d", v) == 3) {
          use(vertices, v[0], cmd), use(tcoords, v[1], cmd), use(normals, v[2], cmd);
        } else if (cmd == "f" && objScan(p, end, "%d//%d", v) == 2) {
          use(vertices, v[0], cmd), use(normals, v[1], cmd);
        } else if (cmd == "f" && objScan(p, end, "%d/%d", v) == 2) {
          use(vertices, v[0], cmd), use(tcoords, v[1], cmd);
        } else if (cmd == "l" && objScan(p, end, "%d/%d", v) == 2) {
          use(vertices, v[0], cmd);  // VTK ignores a line's texture index
        } else if (objScan(p, end, "%d", v) == 1) {
          use(vertices, v[0], cmd);
        } else if (terminated && end - p == 1 && *p == '\\') {
          // a backslash before the newline continues the element on the next line
          if (!nextLine()) break;  // VTK reports the missing line itself
          i = 0;
          continue;
        } else {
          std::size_t wb, we;
          firstWord(line, i, wb, we);
          throw UsageError(at() + cmd + ": '" + line.substr(wb, std::min<std::size_t>(we - wb, 40)) + "' is not an index");
        }
        while (i < line.size() && !std::isspace(static_cast<unsigned char>(line[i]))) ++i;  // VTK skips the word
      }
    }
  }
  tcoords.current = std::max(tcoords.current, tcoordLines);
  for (const Kind* k : {&vertices, &tcoords, &normals})
    if (k->largest > k->current) {
      lineNo = k->largestLine;
      throw UsageError(at() + k->largestCommand + ": " + k->name + " index " + std::to_string(k->largest) + " out of range 1.." +
                       std::to_string(k->current) + " (the file has " + std::to_string(k->current) + ")");
    }
}

// Every cell must name points that exist: VTK's filters index without checking.
void checkCells(const std::string& path, vtkPolyData* pd) {
  const vtkIdType np = pd->GetNumberOfPoints();
  vtkCellArray* arrays[4] = {pd->GetVerts(), pd->GetLines(), pd->GetPolys(), pd->GetStrips()};
  vtkNew<vtkIdList> ids;
  vtkIdType cell = 0;
  const char* kinds[4] = {"vertex", "line", "polygon", "strip"};
  for (int ai = 0; ai < 4; ++ai) {
    vtkCellArray* a = arrays[ai];
    if (!a) continue;
    // The cell layout itself first (offsets from 0, never falling, ending at the connectivity's
    // length): a file whose offsets disagree would send the traversal out of range (fuzzing).
    vtkDataArray* off = a->GetOffsetsArray();
    vtkDataArray* con = a->GetConnectivityArray();
    if (off && con && off->GetNumberOfTuples() > 0) {
      const vtkIdType n = off->GetNumberOfTuples(), len = con->GetNumberOfTuples();
      double prev = 0;
      for (vtkIdType i = 0; i < n; ++i) {
        const double o = off->GetComponent(i, 0);
        if (!(o >= prev) || o > double(len) || (i == 0 && o != 0) || (i + 1 == n && o != double(len)))
          throw UsageError(path + ": " + kinds[ai] + " cells: offset " + std::to_string(i) + " (" +
                           std::to_string(static_cast<long long>(o)) + ") does not fit the " + std::to_string(len) +
                           " point ids of the cells");
        prev = o;
      }
    }
    for (a->InitTraversal(); a->GetNextCell(ids); ++cell)
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k)
        if (ids->GetId(k) < 0 || ids->GetId(k) >= np)
          throw UsageError(path + ": cell " + std::to_string(cell) + " refers to point " + std::to_string(ids->GetId(k)) +
                           " of " + std::to_string(np));
  }
}

// Point and cell data arrays of the wrong length are dropped: VTK's filters copy attributes by
// index without checking (vtkOBJReader, for one, leaves a file's lines' points without normals
// and texture coordinates in arrays shorter than the points; vtkTriangleFilter then reads past
// their end). The geometry is kept; only the arrays that do not fit go.
void dropMisfitArrays(vtkPolyData* pd) {
  const vtkIdType np = pd->GetNumberOfPoints(), nc = pd->GetNumberOfCells();
  for (auto [data, n] : {std::pair<vtkDataSetAttributes*, vtkIdType>{pd->GetPointData(), np}, {pd->GetCellData(), nc}})
    for (int i = data->GetNumberOfArrays() - 1; i >= 0; --i)
      if (vtkAbstractArray* a = data->GetAbstractArray(i); a && a->GetNumberOfTuples() != n) data->RemoveArray(i);
}

}  // namespace

bool isGeometryFile(const std::string& path) {
  const std::string e = extension(path);
  return e == ".vtp" || e == ".vtk" || e == ".stl" || e == ".obj" || e == ".ply";
}

LoadedGeometry readGeometryInProcess(const std::string& path) {
  requireInputFile(path);
  const std::string e = extension(path);
  vtkSmartPointer<vtkAlgorithm> reader;
  if (e == ".vtp") {
    checkVtp(path);
    auto r = vtkSmartPointer<vtkXMLPolyDataReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  } else if (e == ".vtk") {
    auto r = vtkSmartPointer<vtkPolyDataReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  } else if (e == ".stl") {
    checkStl(path);
    auto r = vtkSmartPointer<vtkSTLReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  } else if (e == ".obj") {
    checkObj(path);
    auto r = vtkSmartPointer<vtkOBJReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  } else if (e == ".ply") {
    checkPly(path);
    auto r = vtkSmartPointer<vtkPLYReader>::New();
    r->SetFileName(path.c_str());
    reader = r;
  } else {
    throw UsageError(path + ": unsupported file type '" + e + "' (expected .vtp .vtk .stl .obj .ply)");
  }
  vtkNew<ErrorCatcher> catcher;
  reader->AddObserver(vtkCommand::ErrorEvent, catcher);
  reader->AddObserver(vtkCommand::WarningEvent, catcher);
  try {
    reader->Update();
  } catch (const std::bad_alloc&) {
    // VTK's readers size their arrays from counts in the file (fuzzing: a .vtp or .stl whose
    // counts ask for terabytes): bad input, not an internal failure.
    throw UsageError(path + ": the file's counts ask for more memory than there is (corrupt, or not a " + e +
                     " file)");
  } catch (const std::length_error&) {  // (a count past what a vector may hold: the same)
    throw UsageError(path + ": the file's counts are past what can be held (corrupt, or not a " + e + " file)");
  }
  vtkPolyData* pd = vtkPolyData::SafeDownCast(reader->GetOutputDataObject(0));
  if (!catcher->message.empty()) throw UsageError(path + ": " + catcher->message);
  if (!pd || pd->GetNumberOfPoints() == 0)
    throw UsageError(path + ": no points (not a polygonal data file, or empty)");
  checkCells(path, pd);
  dropMisfitArrays(pd);

  LoadedGeometry g;
  // Lines and polylines.
  vtkPoints* pts = pd->GetPoints();
  vtkUnsignedCharArray* rgb = vtkUnsignedCharArray::SafeDownCast(pd->GetPointData()->GetScalars());
  // Point colours (uchar RGB / RGBA, or one grey value) multiply the shading.
  const bool colours = rgb && rgb->GetNumberOfComponents() >= 1;
  auto colourOf = [&](vtkIdType id) {
    if (rgb->GetNumberOfComponents() < 3) return glm::vec3(float(rgb->GetComponent(id, 0)) / 255.0f);
    return glm::vec3(rgb->GetComponent(id, 0), rgb->GetComponent(id, 1), rgb->GetComponent(id, 2)) / 255.0f;
  };
  if (pd->GetNumberOfLines() > 0) {
    vtkCellArray* lines = pd->GetLines();
    vtkNew<vtkIdList> ids;
    g.lines.starts.push_back(0);
    for (lines->InitTraversal(); lines->GetNextCell(ids);) {
      if (ids->GetNumberOfIds() < 2) continue;
      for (vtkIdType k = 0; k < ids->GetNumberOfIds(); ++k) {
        double p[3];
        pts->GetPoint(ids->GetId(k), p);
        g.lines.points.emplace_back(p[0], p[1], p[2]);
        if (colours) g.lines.colours.push_back(colourOf(ids->GetId(k)));
      }
      g.lines.starts.push_back(std::uint32_t(g.lines.points.size()));
    }
    if (g.lines.points.empty()) g.lines.starts.clear();
  }
  // Polygons and strips: triangulated, with point normals (VTK's own, feature edges split).
  if (pd->GetNumberOfPolys() > 0 || pd->GetNumberOfStrips() > 0) {
    // Polygons with a non-finite point go round VTK's filters: the normals filter would spread
    // their NaN normals to every finite neighbour. They are appended afterwards as fans on the
    // same point ids (the filters keep the input points first, in order), so the renderer skips
    // and counts them (stats.rejectedNonFinite) and the rest shades as if they were not there.
    std::vector<std::vector<vtkIdType>> nonFinite;
    if (vtkCellArray* polys = pd->GetPolys(); polys && polys->GetNumberOfCells() > 0) {
      vtkNew<vtkCellArray> kept;
      vtkNew<vtkIdList> ids;
      for (polys->InitTraversal(); polys->GetNextCell(ids);) {
        bool finite = true;
        for (vtkIdType k = 0; k < ids->GetNumberOfIds() && finite; ++k) {
          double q[3];
          pts->GetPoint(ids->GetId(k), q);
          finite = std::isfinite(q[0]) && std::isfinite(q[1]) && std::isfinite(q[2]);
        }
        if (finite) kept->InsertNextCell(ids);
        else nonFinite.emplace_back(ids->begin(), ids->end());
      }
      if (!nonFinite.empty()) {
        pd->GetCellData()->Initialize();  // per-cell arrays no longer match the cells
        pd->SetPolys(kept);
      }
    }
    vtkNew<vtkTriangleFilter> tri;
    tri->SetInputData(pd);
    tri->PassLinesOff();
    tri->PassVertsOff();
    vtkNew<vtkPolyDataNormals> normals;
    normals->SetInputConnection(tri->GetOutputPort());
    normals->SetFeatureAngle(60.0);
    normals->ConsistencyOn();
    normals->Update();
    vtkPolyData* t = normals->GetOutput();
    vtkDataArray* n = t->GetPointData()->GetNormals();
    vtkUnsignedCharArray* trgb = vtkUnsignedCharArray::SafeDownCast(t->GetPointData()->GetScalars());
    const bool tcol = trgb && trgb->GetNumberOfComponents() >= 3;
    // Texture coordinates (OBJ vt, PLY u v / s t, VTK TCoords): the mesh's own (u, v) for colour
    // maps and for growing fur and scales (surface/mesh_surface.h). Dropped whole when one is
    // not finite.
    vtkDataArray* tc = t->GetPointData()->GetTCoords();
    if (tc && tc->GetNumberOfComponents() < 2) tc = nullptr;
    for (vtkIdType i = 0; tc && i < t->GetNumberOfPoints(); ++i)
      if (!std::isfinite(tc->GetComponent(i, 0)) || !std::isfinite(tc->GetComponent(i, 1))) tc = nullptr;
    for (vtkIdType i = 0; i < t->GetNumberOfPoints(); ++i) {
      if (tc) g.mesh.uvs.emplace_back(tc->GetComponent(i, 0), tc->GetComponent(i, 1));
      double p[3];
      t->GetPoint(i, p);
      g.mesh.positions.emplace_back(p[0], p[1], p[2]);
      if (n) {
        double v[3];
        n->GetTuple(i, v);
        g.mesh.normals.emplace_back(v[0], v[1], v[2]);
      }
      if (tcol)
        g.mesh.colours.emplace_back(glm::vec3(trgb->GetComponent(i, 0), trgb->GetComponent(i, 1), trgb->GetComponent(i, 2)) / 255.0f);
    }
    vtkCellArray* polys = t->GetPolys();
    vtkNew<vtkIdList> ids;
    for (polys->InitTraversal(); polys->GetNextCell(ids);)
      if (ids->GetNumberOfIds() == 3)
        g.mesh.triangles.emplace_back(std::uint32_t(ids->GetId(0)), std::uint32_t(ids->GetId(1)), std::uint32_t(ids->GetId(2)));
    for (const std::vector<vtkIdType>& poly : nonFinite)
      for (size_t k = 1; k + 1 < poly.size(); ++k)
        if (poly[0] < vtkIdType(g.mesh.positions.size()) && poly[k] < vtkIdType(g.mesh.positions.size()) &&
            poly[k + 1] < vtkIdType(g.mesh.positions.size()))
          g.mesh.triangles.emplace_back(std::uint32_t(poly[0]), std::uint32_t(poly[k]), std::uint32_t(poly[k + 1]));
  }
  if (g.mesh.triangles.empty() && g.lines.points.empty())
    throw UsageError(path + ": no polygons or lines to draw");
  return g;
}

namespace {

const std::string kMeshMagic("WFMSH1\n\0", 8);

void writeLoaded(BlobWriter& w, const LoadedGeometry& g) {
  const wf::TriangleMesh& m = g.mesh;
  w.vec(m.positions), w.vec(m.normals), w.vec(m.uvs), w.vec(m.colours), w.vec(m.triangles);
  w.vec(g.lines.points), w.vec(g.lines.colours), w.vec(g.lines.starts);
}

// What the worker wrote, checked as the renderer relies on it before anyone indexes it.
LoadedGeometry readLoaded(BlobReader& r) {
  const auto bad = [] { return std::runtime_error("the mesh worker's result is inconsistent"); };
  LoadedGeometry g;
  wf::TriangleMesh& m = g.mesh;
  m.positions = r.vec<glm::dvec3>();
  m.normals = r.vec<glm::dvec3>();
  m.uvs = r.vec<glm::dvec2>();
  m.colours = r.vec<glm::vec3>();
  m.triangles = r.vec<glm::uvec3>();
  g.lines.points = r.vec<glm::dvec3>();
  g.lines.colours = r.vec<glm::vec3>();
  g.lines.starts = r.vec<std::uint32_t>();
  const size_t nv = m.positions.size();
  for (size_t n : {m.normals.size(), m.uvs.size(), m.colours.size()})
    if (n != 0 && n != nv) throw bad();
  for (const glm::uvec3& t : m.triangles)
    if (t.x >= nv || t.y >= nv || t.z >= nv) throw bad();
  if (!g.lines.colours.empty() && g.lines.colours.size() != g.lines.points.size()) throw bad();
  if (!polylineStartsFit(g.lines.starts, g.lines.points.size())) throw bad();
  if (m.triangles.empty() && g.lines.points.empty()) throw bad();  // the reader refuses a file with neither
  if (!r.atEnd()) throw bad();
  return g;
}

}  // namespace

LoadedGeometry readGeometry(const std::string& path, bool isolate, double timeoutSeconds) {
  requireInputFile(path);
  if (!isGeometryFile(path))  // the extension first: no process for a name it cannot be
    throw UsageError(path + ": unsupported file type '" + extension(path) + "' (expected .vtp .vtk .stl .obj .ply)");
  if (!isolate || !readerWorkersEnabled()) return readGeometryInProcess(path);
  ReaderWorkerCall call;
  call.mode = "mesh-worker";
  call.magic = kMeshMagic;
  call.workerName = "mesh worker";
  call.what = "reading";
  call.library = "VTK's reader";
  call.cannotRead = "it is corrupt, or not a " + extension(path) + " file VTK 9.1 can read";
  call.timeoutHint = "--read-timeout S sets the limit";
  call.timeoutSeconds = timeoutSeconds;
  const std::string body = runReaderWorker(path, call);
  BlobReader r(body);
  return readLoaded(r);
}

int runMeshWorker(const std::vector<std::string>& a) {
  if (a.size() != 4) {
    std::fprintf(stderr, "wirefur: mesh-worker is internal (FILE OUT PARENT TIMEOUT)\n");
    return wf::kWorkerExitUsage;
  }
  wf::becomeWorker(a[2], a[3]);
  vtkObject::GlobalWarningDisplayOff();
  finishReaderWorker(a[0], a[1], kMeshMagic, [&](BlobWriter& w) { writeLoaded(w, readGeometryInProcess(a[0])); });
}

void writePolylinesVtp(const wf::PolylineSet& lines, const std::string& path) {
  vtkNew<vtkPolyData> pd;
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToFloat();
  for (const glm::dvec3& p : lines.points) pts->InsertNextPoint(p.x, p.y, p.z);
  vtkNew<vtkCellArray> cells;
  for (size_t i = 0; i < lines.polylineCount(); ++i) {
    cells->InsertNextCell(vtkIdType(lines.starts[i + 1] - lines.starts[i]));
    for (std::uint32_t k = lines.starts[i]; k < lines.starts[i + 1]; ++k) cells->InsertCellPoint(k);
  }
  pd->SetPoints(pts);
  pd->SetLines(cells);
  vtkNew<vtkXMLPolyDataWriter> w;
  w->SetFileName(path.c_str());
  w->SetInputData(pd);
  w->SetDataModeToBinary();
  if (!w->Write()) throw std::runtime_error("cannot write " + path);
}

}  // namespace wfapp
