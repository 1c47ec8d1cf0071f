// What the CAD readers hand to the tessellator: parts (a shape with its placement, name and
// colours), read from STEP / IGES (XCAF), BREP or FreeCAD documents. OpenCASCADE types; private
// to the WireFur::CAD module.
#pragma once

#include <Quantity_Color.hxx>
#include <TopLoc_Location.hxx>
#include <TopoDS_Shape.hxx>

#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace wfcad {

/// Bad input: the message names the entity and the problem ("entity #12: ..."); the reader puts
/// the file name in front.
struct CadError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Part {
  std::string name;
  TopoDS_Shape shape;          ///< as stored (its own location included)
  TopLoc_Location placement;   ///< where this instance goes (identity for a plain shape)
  std::optional<Quantity_Color> colour;
  /// Per face, in TopExp_Explorer(shape, FACE) order, or empty: overrides `colour`.
  std::vector<std::optional<Quantity_Color>> faceColours;
};

struct Model {
  std::vector<Part> parts;
};

/// Readers by format. `path` is the file to read; throw CadError on bad input.
Model readStepOrIges(const std::string& path, bool iges);
Model readBrep(const std::string& path);
Model readFreeCad(const std::string& path);

/// Reads a BREP text (or, with `binary`, OpenCASCADE's binary form) from memory; throws CadError.
TopoDS_Shape brepFromMemory(const std::string& bytes, bool binary, const std::string& entity);

/// True when `head` (a file's first bytes) is a BREP file; `binary` tells which form.
bool looksLikeBrep(const std::string& head, bool& binary);

/// Collects OpenCASCADE's messages while a reader runs instead of printing them; the first
/// failure is kept for the error line.
class MessageCapture {
 public:
  MessageCapture();
  ~MessageCapture();
  MessageCapture(const MessageCapture&) = delete;
  MessageCapture& operator=(const MessageCapture&) = delete;
  /// The first message of gravity Fail (or Alarm when there was no Fail), one line; empty if none.
  std::string firstFailure() const;
};

}  // namespace wfcad
