// Whether the X display can be opened (Xlib kept in its own file: its macros, None among them,
// clash with ordinary names elsewhere).
#pragma once

namespace wfapp {

/// True when DISPLAY names an X server that accepts a connection.
bool canOpenXDisplay();

}  // namespace wfapp
