// `wirefur gallery`: every picture the toolkit can make so far, with caption, time and error,
// into a folder with an index.html.
#pragma once

#include <string>

namespace wfapp {

struct GalleryOptions {
  std::string outDir = "out";
  int size = 512;
  bool quiet = false;
};

int runGallery(const GalleryOptions& options);

}  // namespace wfapp
