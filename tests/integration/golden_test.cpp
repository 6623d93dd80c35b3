// Golden files: the CLI's outputs for the small inputs in golden/ must not change unnoticed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli_runner.h"
#include "file_bytes.h"

namespace fs = std::filesystem;

namespace {

void compare_reports(const nlohmann::json& want, const nlohmann::json& got, const std::string& where) {
  if (want.is_object()) {
    for (auto it = want.begin(); it != want.end(); ++it) {
      if (it.key() == "seconds" || it.key() == "source") continue;  // time varies; source names paths
      ASSERT_TRUE(got.contains(it.key())) << where << "." << it.key();
      compare_reports(*it, got[it.key()], where + "." + it.key());
    }
  } else if (want.is_array()) {  // per-level figures: element by element, with the same tolerance
    ASSERT_TRUE(got.is_array() && got.size() == want.size()) << where;
    for (size_t i = 0; i < want.size(); ++i) compare_reports(want[i], got[i], where + "[" + std::to_string(i) + "]");
  } else if (want.is_number_float()) {
    const double a = want.get<double>(), b = got.get<double>();
    EXPECT_NEAR(a, b, 1e-9 * std::max(std::fabs(a), 1e-30)) << where;
  } else {
    EXPECT_EQ(want, got) << where;
  }
}

}  // namespace

TEST(Golden, OutputsMatchStoredFiles) {
  const fs::path root = fs::path(AHD_SOURCE_DIR) / "golden";
  std::ifstream cases(root / "cases.txt");
  ASSERT_TRUE(cases) << "golden/cases.txt missing";
  const fs::path tmp = ahd_test::temp_dir("golden");
  std::string name, input, profile, container;
  int n = 0;
  while (cases >> name >> input >> profile >> container) {
    ++n;
    const fs::path out = tmp / (name + "." + container);
    const auto res = ahd_test::run_cli({"convert", (root / "inputs" / input).string(), "-o", out.string(), "--profile",
                                        profile, "--threads", "1", "--measure", "full", "-q"});
    ASSERT_EQ(res.exit_code, 0) << res.output;
    int files = 0;
    for (const auto& e : fs::directory_iterator(root / "expected")) {
      const std::string fn = e.path().filename().string();
      if (fn.rfind(name + ".", 0) != 0) continue;
      ++files;
      ASSERT_TRUE(fs::exists(tmp / fn)) << fn << " was not written";
      if (fn.size() > 12 && fn.substr(fn.size() - 12) == ".report.json") {
        compare_reports(nlohmann::json::parse(ahd_test::read_text(e.path())), nlohmann::json::parse(ahd_test::read_text(tmp / fn)), fn);
      } else {
        EXPECT_EQ(ahd_test::read_text(e.path()), ahd_test::read_text(tmp / fn)) << fn << " differs from golden/expected (regenerate on purpose with scripts/regen-golden.sh)";
      }
    }
    EXPECT_GE(files, 4) << name;
  }
  EXPECT_GE(n, 4);
  fs::remove_all(tmp);
}
