// Found by fuzz_godot_scene (issue 44): a .tscn whose transform is a multi-line value with a bad
// number gave an error quoting the token with its line break and control characters — two lines
// where the contract is one. The cause is now escaped (\n, \xNN) and a long token cut. Unit test:
// in process, the parser alone.
#include <gtest/gtest.h>

#include <string>

#include "bakers/godot/godot_tscn.h"
#include "core/error.h"

TEST(GodotTscnMessagesUnit, BadNumberInAMultiLineTransformIsOneLine) {
  const std::string tscn = "[gd_scene format=3]\n\n[node name=\"A\" type=\"Node3D\"]\n"
                           "transform = Transform3D(1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 2\nx\f)\n";
  try {
    ahd::parse_godot_tscn(tscn, "f.tscn");
    ADD_FAILURE() << "accepted";
  } catch (const ahd::Error& e) {
    EXPECT_EQ(std::string(e.what()), "f.tscn: line 5: Transform3D number ' 2\\nx\\x0c'");
  }
  const std::string long_token = "[gd_scene format=3]\n\n[node name=\"A\" type=\"Node3D\"]\n"
                                 "transform = Transform3D(1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, " + std::string(1000, 'z') + ")\n";
  try {
    ahd::parse_godot_tscn(long_token, "f.tscn");
    ADD_FAILURE() << "accepted";
  } catch (const ahd::Error& e) {
    EXPECT_LT(std::string(e.what()).size(), 200u) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
  }
}
