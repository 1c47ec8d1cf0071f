// Scene-file keys of the surface, texture, burnish and growth issue, through `wirefur render`.
#include "cli_support.h"

#include <gtest/gtest.h>
