#include "x_display.h"

#include <X11/Xlib.h>

#include <cstdlib>

namespace wfapp {

bool canOpenXDisplay() {
  if (!std::getenv("DISPLAY")) return false;
  Display* display = XOpenDisplay(nullptr);
  if (!display) return false;
  XCloseDisplay(display);
  return true;
}

}  // namespace wfapp
