// role_name: the ;TYPE: words of the G-code, one per role.
#include "geometry/toolpaths/toolpaths.h"

#include <doctest/doctest.h>

#include <set>
#include <string>

namespace toolpaths_test {

using namespace geometry;

TEST_CASE("role_names_are_cura_words_and_distinct") {
  CHECK(role_name(PathRole::skirt) == "SKIRT");
  CHECK(role_name(PathRole::outer_wall) == "WALL-OUTER");
  CHECK(role_name(PathRole::inner_wall) == "WALL-INNER");
  CHECK(role_name(PathRole::sparse_infill) == "FILL");
  CHECK(role_name(PathRole::support) == "SUPPORT");
  CHECK(role_name(PathRole::support_interface) == "SUPPORT-INTERFACE");
  CHECK(role_name(PathRole::bridge) == "BRIDGE");
  std::set<std::string> names;
  for (PathRole r : {PathRole::skirt, PathRole::outer_wall, PathRole::inner_wall,
                     PathRole::thin_wall, PathRole::bottom_skin, PathRole::top_skin,
                     PathRole::solid_infill, PathRole::sparse_infill, PathRole::support,
                     PathRole::support_interface, PathRole::bridge, PathRole::brim,
                     PathRole::raft}) {
    const std::string name(role_name(r));
    CHECK(!name.empty());
    CHECK(name.find(' ') == std::string::npos);
    names.insert(name);
  }
  CHECK(names.size() == 13);
}

TEST_CASE("support_roles_are_support_interface_and_raft") {
  CHECK(is_support_role(PathRole::support));
  CHECK(is_support_role(PathRole::support_interface));
  CHECK(is_support_role(PathRole::raft));
  CHECK_FALSE(is_support_role(PathRole::bridge));
  CHECK_FALSE(is_support_role(PathRole::brim));
  CHECK_FALSE(is_support_role(PathRole::outer_wall));
}

}  // namespace toolpaths_test
