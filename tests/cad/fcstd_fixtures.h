// Minimal FreeCAD documents for the CAD reader's tests, in the layout FreeCAD 0.19 - 0.21 saves:
// a zip of Document.xml, GuiDocument.xml (optional) and BREP texts. Only what the reader reads is
// written, with FreeCAD's element and attribute names and its property types.
#pragma once

#include "cad_fixtures.h"

#include <TopLoc_Location.hxx>
#include <gp_Quaternion.hxx>

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace cadtest::fc {

/// FreeCAD's Base::Placement: a translation after a rotation, the rotation a unit quaternion
/// saved as Q0..Q3 = (x, y, z, w) (with its angle A in radians and axis Ox Oy Oz).
struct Placement {
  double px = 0, py = 0, pz = 0;
  double q[4] = {0, 0, 0, 1};
  double angle = 0, axis[3] = {0, 0, 1};

  /// `degrees` about the axis (ax, ay, az), through the origin.
  static Placement rotation(double ax, double ay, double az, double degrees) {
    Placement p;
    const double n = std::sqrt(ax * ax + ay * ay + az * az), h = degrees * 3.14159265358979323846 / 360.0;
    p.q[0] = ax / n * std::sin(h), p.q[1] = ay / n * std::sin(h), p.q[2] = az / n * std::sin(h), p.q[3] = std::cos(h);
    p.angle = 2 * h, p.axis[0] = ax / n, p.axis[1] = ay / n, p.axis[2] = az / n;
    return p;
  }
  Placement translated(double x, double y, double z) const {
    Placement p = *this;
    p.px = x, p.py = y, p.pz = z;
    return p;
  }
  /// As an OpenCASCADE location: used only to store the shape the way FreeCAD does (its location
  /// equal to the Placement); the tests' expectations are computed by hand.
  TopLoc_Location location() const {
    gp_Trsf t;
    t.SetRotation(gp_Quaternion(q[0], q[1], q[2], q[3]));
    t.SetTranslationPart(gp_Vec(px, py, pz));
    return TopLoc_Location(t);
  }
};

/// An object of Document.xml: a Part::Feature with a shape file, or an App::Part container.
struct Object {
  std::string name, type, label;
  Placement placement;
  std::string shapeFile;               // Part::Feature
  std::vector<std::string> group;      // App::Part
  std::optional<bool> visibility;      // the object's own Visibility property, if written

  static Object feature(const std::string& name, const std::string& label, const Placement& p, const std::string& file) {
    Object o;
    o.name = name, o.type = "Part::Feature", o.label = label, o.placement = p, o.shapeFile = file;
    return o;
  }
  static Object container(const std::string& name, const std::string& label, const Placement& p,
                          const std::vector<std::string>& children) {
    Object o;
    o.name = name, o.type = "App::Part", o.label = label, o.placement = p, o.group = children;
    return o;
  }
};

/// A view provider of GuiDocument.xml.
struct View {
  std::string name;
  bool visible = true;
  std::optional<std::uint32_t> shapeColor;  // packed (r << 24) | (g << 16) | (b << 8) | a
};

inline std::uint32_t packColour(unsigned r, unsigned g, unsigned b, unsigned a = 0) {
  return (std::uint32_t(r) << 24) | (std::uint32_t(g) << 16) | (std::uint32_t(b) << 8) | std::uint32_t(a);
}

inline std::string num(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

inline std::string documentXml(const std::vector<Object>& objects) {
  std::string s =
      "<?xml version='1.0' encoding='utf-8'?>\n"
      "<!--\n FreeCAD Document, see https://www.freecad.org for more information...\n-->\n"
      "<Document SchemaVersion=\"4\" ProgramVersion=\"0.21R33771 (Git)\" FileVersion=\"1\">\n"
      "    <Properties Count=\"1\" TransientCount=\"0\">\n"
      "        <Property name=\"Label\" type=\"App::PropertyString\" status=\"1\">\n"
      "            <String value=\"Unnamed\"/>\n"
      "        </Property>\n"
      "    </Properties>\n";
  s += "    <Objects Count=\"" + std::to_string(objects.size()) + "\" Dependencies=\"1\">\n";
  for (const Object& o : objects) s += "        <ObjectDeps Name=\"" + o.name + "\" Count=\"0\"/>\n";
  int id = 1;
  for (const Object& o : objects)
    s += "        <Object type=\"" + o.type + "\" name=\"" + o.name + "\" id=\"" + std::to_string(id++) + "\" />\n";
  s += "    </Objects>\n";
  s += "    <ObjectData Count=\"" + std::to_string(objects.size()) + "\">\n";
  for (const Object& o : objects) {
    s += "        <Object name=\"" + o.name + "\"" + (o.type == "App::Part" ? " Extensions=\"True\"" : "") + ">\n";
    if (o.type == "App::Part")
      s += "            <Extensions Count=\"1\">\n"
           "                <Extension type=\"App::OriginGroupExtension\" name=\"OriginGroupExtension\">\n"
           "                </Extension>\n"
           "            </Extensions>\n";
    s += "            <Properties Count=\"4\" TransientCount=\"0\">\n";
    if (!o.group.empty()) {
      s += "                <Property name=\"Group\" type=\"App::PropertyLinkList\" status=\"1\">\n";
      s += "                    <LinkList count=\"" + std::to_string(o.group.size()) + "\">\n";
      for (const std::string& c : o.group) s += "                        <Link value=\"" + c + "\"/>\n";
      s += "                    </LinkList>\n                </Property>\n";
    }
    s += "                <Property name=\"Label\" type=\"App::PropertyString\" status=\"134217728\">\n"
         "                    <String value=\"" + o.label + "\"/>\n"
         "                </Property>\n";
    const Placement& p = o.placement;
    s += "                <Property name=\"Placement\" type=\"App::PropertyPlacement\" status=\"8388608\">\n"
         "                    <PropertyPlacement Px=\"" + num(p.px) + "\" Py=\"" + num(p.py) + "\" Pz=\"" + num(p.pz) +
         "\" Q0=\"" + num(p.q[0]) + "\" Q1=\"" + num(p.q[1]) + "\" Q2=\"" + num(p.q[2]) + "\" Q3=\"" + num(p.q[3]) +
         "\" A=\"" + num(p.angle) + "\" Ox=\"" + num(p.axis[0]) + "\" Oy=\"" + num(p.axis[1]) + "\" Oz=\"" + num(p.axis[2]) +
         "\"/>\n"
         "                </Property>\n";
    if (!o.shapeFile.empty())
      s += "                <Property name=\"Shape\" type=\"Part::PropertyPartShape\" status=\"1\">\n"
           "                    <Part file=\"" + o.shapeFile + "\"/>\n"
           "                </Property>\n";
    if (o.visibility)
      s += "                <Property name=\"Visibility\" type=\"App::PropertyBool\" status=\"9\">\n"
           "                    <Bool value=\"" + std::string(*o.visibility ? "true" : "false") + "\"/>\n"
           "                </Property>\n";
    s += "            </Properties>\n        </Object>\n";
  }
  s += "    </ObjectData>\n</Document>\n";
  return s;
}

inline std::string guiDocumentXml(const std::vector<View>& views) {
  std::string s =
      "<?xml version='1.0' encoding='utf-8'?>\n"
      "<Document SchemaVersion=\"1\" HasExpansion=\"1\">\n";
  s += "    <ViewProviderData Count=\"" + std::to_string(views.size()) + "\">\n";
  for (const View& v : views) {
    s += "        <ViewProvider name=\"" + v.name + "\" expanded=\"0\">\n";
    s += "            <Properties Count=\"2\" TransientCount=\"0\">\n";
    if (v.shapeColor)
      s += "                <Property name=\"ShapeColor\" type=\"App::PropertyColor\" status=\"0\">\n"
           "                    <PropertyColor value=\"" + std::to_string(*v.shapeColor) + "\"/>\n"
           "                </Property>\n";
    s += "                <Property name=\"Visibility\" type=\"App::PropertyBool\" status=\"0\">\n"
         "                    <Bool value=\"" + std::string(v.visible ? "true" : "false") + "\"/>\n"
         "                </Property>\n";
    s += "            </Properties>\n        </ViewProvider>\n";
  }
  s += "    </ViewProviderData>\n"
       "    <Camera settings=\"  OrthographicCamera {&#10;  viewportMapping ADJUST_CAMERA&#10; }&#10;\"/>\n"
       "</Document>\n";
  return s;
}

/// Writes the document: Document.xml, GuiDocument.xml (when `views` is given) and `files`.
inline std::string writeFcstd(const std::string& name, const std::vector<Object>& objects,
                              const std::optional<std::vector<View>>& views,
                              const std::vector<std::pair<std::string, std::string>>& files) {
  std::vector<std::pair<std::string, std::string>> entries = {{"Document.xml", documentXml(objects)}};
  if (views) entries.emplace_back("GuiDocument.xml", guiDocumentXml(*views));
  for (const auto& f : files) entries.push_back(f);
  return writeZip(name, entries);
}

}  // namespace cadtest::fc
