// FreeCAD documents (.FCStd): a zip (read with libzip) of Document.xml, GuiDocument.xml and one
// BREP file per shape (read with pugixml and OpenCASCADE). What of FreeCAD's model is read is
// listed in docs/cad.md: objects with a Part shape, their Label, Placement (App::Part containers
// composed), Visibility, ShapeColor and per-face DiffuseColor.
#include "wf_cad_model.h"

#include <TopExp_Explorer.hxx>
#include <gp_Quaternion.hxx>
#include <gp_Trsf.hxx>
#include <gp_Vec.hxx>

#include <pugixml.hpp>
#include <zip.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <set>

namespace wfcad {

namespace {

// Entries larger than this are refused before they are inflated (a zip bomb, or not FreeCAD's).
constexpr zip_uint64_t kMaxEntryBytes = zip_uint64_t(2) << 30;

struct ZipCloser {
  void operator()(zip_t* z) const { zip_discard(z); }
};

class Archive {
 public:
  explicit Archive(const std::string& path) {
    int err = 0;
    zip_t* z = zip_open(path.c_str(), ZIP_RDONLY | ZIP_CHECKCONS, &err);
    if (!z) {
      zip_error_t e;
      zip_error_init_with_code(&e, err);
      const std::string why = zip_error_strerror(&e);
      zip_error_fini(&e);
      throw CadError("not a readable zip archive (a FreeCAD document is one): " + why);
    }
    zip_.reset(z);
  }
  bool has(const std::string& name) const { return zip_name_locate(zip_.get(), name.c_str(), 0) >= 0; }
  std::string read(const std::string& name) const {
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_stat(zip_.get(), name.c_str(), 0, &st) != 0) throw CadError(name + ": not in the archive");
    if (!(st.valid & ZIP_STAT_SIZE)) throw CadError(name + ": size unknown");
    if (st.size > kMaxEntryBytes) throw CadError(name + ": " + std::to_string(st.size) + " bytes inflated, over the 2 GiB limit");
    std::unique_ptr<zip_file_t, int (*)(zip_file_t*)> f(zip_fopen(zip_.get(), name.c_str(), 0), zip_fclose);
    if (!f) throw CadError(name + ": cannot be opened in the archive: " + zip_strerror(zip_.get()));
    // The size in the archive's directory may lie: memory grows with what actually inflates,
    // never ahead of it by more than a chunk, and stops at the limit.
    std::string out;
    out.reserve(size_t(std::min<zip_uint64_t>(st.size, zip_uint64_t(1) << 24)));
    char chunk[1 << 16];
    while (true) {
      const zip_int64_t n = zip_fread(f.get(), chunk, sizeof chunk);
      if (n < 0) throw CadError(name + ": corrupt entry: " + zip_file_strerror(f.get()));
      if (n == 0) break;
      if (out.size() + size_t(n) > st.size) throw CadError(name + ": inflates past the " + std::to_string(st.size) + " bytes the archive declares");
      out.append(chunk, size_t(n));
    }
    if (out.size() != st.size)
      throw CadError(name + ": truncated entry (" + std::to_string(out.size()) + " of " + std::to_string(st.size) + " bytes)");
    return out;
  }

 private:
  std::unique_ptr<zip_t, ZipCloser> zip_;
};

pugi::xml_document parseXml(const std::string& entry, const std::string& text) {
  pugi::xml_document doc;
  const pugi::xml_parse_result r = doc.load_buffer(text.data(), text.size());
  if (!r) {
    // The line of the error, for the message.
    size_t line = 1;
    for (ptrdiff_t i = 0; i < r.offset && size_t(i) < text.size(); ++i) line += text[size_t(i)] == '\n';
    throw CadError(entry + ":" + std::to_string(line) + ": " + r.description());
  }
  return doc;
}

pugi::xml_node property(const pugi::xml_node& properties, const char* name) {
  for (pugi::xml_node p : properties.children("Property"))
    if (std::strcmp(p.attribute("name").value(), name) == 0) return p;
  return {};
}

struct DocObject {
  std::string name, type, label, shapeFile;
  gp_Trsf placement;
  std::optional<bool> visible;           // Document.xml's Visibility, if saved
  std::vector<std::string> group;        // App::Part children
};

double attr(const pugi::xml_node& n, const char* a, const std::string& entity) {
  const pugi::xml_attribute at = n.attribute(a);
  if (!at) return 0.0;
  const double v = at.as_double(std::nan(""));
  if (!std::isfinite(v) || std::abs(v) > 1e30) throw CadError(entity + ": Placement " + a + " = '" + at.value() + "' is not a finite number");
  return v;
}

gp_Trsf readPlacement(const pugi::xml_node& prop, const std::string& entity) {
  gp_Trsf t;
  const pugi::xml_node p = prop.child("PropertyPlacement");
  if (!p) return t;
  const double x = attr(p, "Q0", entity), y = attr(p, "Q1", entity), z = attr(p, "Q2", entity), w = attr(p, "Q3", entity);
  const double n = std::sqrt(x * x + y * y + z * z + w * w);
  if (!(n > 1e-12)) throw CadError(entity + ": Placement rotation is a zero quaternion");
  t.SetRotation(gp_Quaternion(x / n, y / n, z / n, w / n));
  t.SetTranslationPart(gp_Vec(attr(p, "Px", entity), attr(p, "Py", entity), attr(p, "Pz", entity)));
  return t;
}

Quantity_Color fromPacked(std::uint32_t v) {
  // FreeCAD packs a colour as (r << 24) | (g << 16) | (b << 8) | transparency, 8 bits each.
  return Quantity_Color(double((v >> 24) & 0xff) / 255.0, double((v >> 16) & 0xff) / 255.0, double((v >> 8) & 0xff) / 255.0,
                        Quantity_TOC_sRGB);
}

struct ViewInfo {
  std::optional<bool> visible;
  std::optional<Quantity_Color> colour;
  std::string diffuseFile;
};

}  // namespace

Model readFreeCad(const std::string& path) {
  const Archive zip(path);
  if (!zip.has("Document.xml")) throw CadError("Document.xml: not in the archive (not a FreeCAD document)");
  const pugi::xml_document doc = parseXml("Document.xml", zip.read("Document.xml"));
  const pugi::xml_node root = doc.child("Document");
  if (!root) throw CadError("Document.xml: no <Document> element");

  std::map<std::string, DocObject> objects;
  std::vector<std::string> order;  // document order
  for (pugi::xml_node o : root.child("Objects").children("Object")) {
    DocObject d;
    d.name = o.attribute("name").value();
    d.type = o.attribute("type").value();
    if (d.name.empty() || objects.count(d.name)) continue;
    order.push_back(d.name);
    objects[d.name] = d;
  }
  for (pugi::xml_node o : root.child("ObjectData").children("Object")) {
    auto it = objects.find(o.attribute("name").value());
    if (it == objects.end()) continue;
    DocObject& d = it->second;
    const std::string entity = "object '" + d.name + "'";
    const pugi::xml_node props = o.child("Properties");
    if (pugi::xml_node p = property(props, "Label")) d.label = p.child("String").attribute("value").value();
    if (pugi::xml_node p = property(props, "Placement")) d.placement = readPlacement(p, entity);
    if (pugi::xml_node p = property(props, "Visibility"); p && p.child("Bool"))
      d.visible = std::strcmp(p.child("Bool").attribute("value").value(), "true") == 0;
    if (pugi::xml_node p = property(props, "Shape"); p && p.child("Part")) d.shapeFile = p.child("Part").attribute("file").value();
    if (pugi::xml_node p = property(props, "Group"))
      for (pugi::xml_node l : p.child("LinkList").children("Link")) d.group.push_back(l.attribute("value").value());
  }

  // GuiDocument.xml (absent when the document was saved without the GUI): visibility and colours.
  std::map<std::string, ViewInfo> views;
  std::string guiText;
  if (zip.has("GuiDocument.xml")) {
    const pugi::xml_document gui = parseXml("GuiDocument.xml", zip.read("GuiDocument.xml"));
    for (pugi::xml_node v : gui.child("Document").child("ViewProviderData").children("ViewProvider")) {
      ViewInfo info;
      const pugi::xml_node props = v.child("Properties");
      if (pugi::xml_node p = property(props, "Visibility"); p && p.child("Bool"))
        info.visible = std::strcmp(p.child("Bool").attribute("value").value(), "true") == 0;
      if (pugi::xml_node p = property(props, "ShapeColor"); p && p.child("PropertyColor"))
        info.colour = fromPacked(std::uint32_t(p.child("PropertyColor").attribute("value").as_ullong()));
      if (pugi::xml_node p = property(props, "DiffuseColor"); p && p.child("ColorList"))
        info.diffuseFile = p.child("ColorList").attribute("file").value();
      views[v.attribute("name").value()] = info;
    }
  }

  // App::Part containers place their children: compose placements down the tree.
  std::map<std::string, gp_Trsf> parentPlacement;
  std::map<std::string, bool> parentVisible;
  auto isVisible = [&](const DocObject& d) {
    auto v = views.find(d.name);
    if (v != views.end() && v->second.visible) return *v->second.visible;
    return d.visible.value_or(true);
  };
  std::function<void(const std::string&, const gp_Trsf&, bool, int)> place = [&](const std::string& name, const gp_Trsf& t,
                                                                                 bool visible, int depth) {
    if (depth > 64) throw CadError("object '" + name + "': containers nested deeper than 64 (a cycle?)");
    auto it = objects.find(name);
    if (it == objects.end()) return;
    // Each object is placed once, by the first container that names it: a document whose
    // containers name the same children over and over (a fan-out found by fuzzing) stays linear.
    if (parentPlacement.count(name)) return;
    const DocObject& d = it->second;
    parentPlacement[name] = t;
    parentVisible[name] = visible;
    if (d.type == "App::Part") {
      const gp_Trsf mine = t * d.placement;
      for (const std::string& child : d.group) place(child, mine, visible && isVisible(d), depth + 1);
    }
  };
  std::set<std::string> children;
  for (auto& [name, d] : objects)
    if (d.type == "App::Part")
      for (const std::string& c : d.group) children.insert(c);
  for (const std::string& name : order)
    if (!children.count(name)) place(name, gp_Trsf(), true, 0);

  Model model;
  int withShape = 0, emptyShapes = 0;
  for (const std::string& name : order) {
    const DocObject& d = objects[name];
    if (d.shapeFile.empty()) continue;
    ++withShape;
    if (!isVisible(d) || !parentVisible.count(name) || !parentVisible[name]) continue;
    const std::string entity = "object '" + d.name + "' (" + d.shapeFile + ")";
    if (!zip.has(d.shapeFile)) throw CadError(entity + ": the shape file is not in the archive");
    const std::string bytes = zip.read(d.shapeFile);
    if (bytes.empty()) {  // FreeCAD writes an empty file for an empty shape
      ++emptyShapes;
      continue;
    }
    bool binary = false;
    if (!looksLikeBrep(bytes.substr(0, 256), binary)) throw CadError(entity + ": not a BREP shape file");
    Part p;
    p.name = d.label.empty() ? d.name : d.label;
    // FreeCAD keeps the shape's own location equal to the Placement property; where they differ
    // the Placement (what FreeCAD's property view shows) is taken.
    p.shape = brepFromMemory(bytes, binary, entity).Located(TopLoc_Location());
    p.placement = TopLoc_Location(parentPlacement[name] * d.placement);
    auto v = views.find(d.name);
    if (v != views.end()) {
      p.colour = v->second.colour;
      if (!v->second.diffuseFile.empty() && zip.has(v->second.diffuseFile)) {
        // ColorList file: a little-endian count, then that many packed colours.
        const std::string list = zip.read(v->second.diffuseFile);
        std::uint32_t n = 0;
        if (list.size() >= 4) std::memcpy(&n, list.data(), 4);
        int faces = 0;
        for (TopExp_Explorer e(p.shape, TopAbs_FACE); e.More(); e.Next()) ++faces;
        if (list.size() >= 4 + 4 * size_t(n) && n > 0) {
          std::vector<Quantity_Color> cs;
          for (std::uint32_t i = 0; i < n; ++i) {
            std::uint32_t c = 0;
            std::memcpy(&c, list.data() + 4 + 4 * i, 4);
            cs.push_back(fromPacked(c));
          }
          if (n == 1) p.colour = cs[0];
          else if (int(n) == faces)
            for (const Quantity_Color& c : cs) p.faceColours.emplace_back(c);
        }
      }
    }
    model.parts.push_back(std::move(p));
  }
  if (withShape == 0) throw CadError("no object with a shape (Document.xml names " + std::to_string(objects.size()) + " objects)");
  if (model.parts.empty() && emptyShapes > 0)
    throw CadError("every visible object's shape is empty (" + std::to_string(emptyShapes) + " of them)");
  if (model.parts.empty()) throw CadError("every object with a shape is hidden (" + std::to_string(withShape) + " of them)");
  return model;
}

}  // namespace wfcad
