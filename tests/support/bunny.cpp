#include "support/bunny.h"

#include <string>

#include "geometry/mesh/placement.h"
#include "geometry/mesh/repair.h"
#include "geometry/mesh/stl_io.h"

namespace test_support {

geometry::Mesh paper_bunny() {
  geometry::Placement placement;
  placement.units_to_mm = 1000;
  placement.up = geometry::Axis::y;
  placement.height = 50;
  return geometry::place(geometry::repair(geometry::read_stl(std::string(MAHOST_DATA_DIR) + "/bunny.stl")),
                         placement);
}

}  // namespace test_support
