// The Stanford bunny of the paper's figures: data/bunny.stl (metres, Y up) repaired and placed
// Z up, 50 mm tall, centred on the bed, as `mahost info data/bunny.stl --up y --units m
// --height 50` places it.
#pragma once

#include "geometry/mesh/mesh.h"

namespace test_support {

geometry::Mesh paper_bunny();

}  // namespace test_support
