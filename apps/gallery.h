// `wirefur gallery`: every picture the toolkit can make so far, with caption, time and error,
// into a folder with an index.html.
#pragma once

#include <string>

namespace wfapp {

struct GalleryOptions {
  std::string outDir = "out/gallery";
  std::string scenesDir;  ///< empty: dataDir() + "/scenes"
  int size = 0;  ///< > 0: scale every scene down so that its longer side is at most this
  bool quiet = false;
};

int runGallery(const GalleryOptions& options);

}  // namespace wfapp
