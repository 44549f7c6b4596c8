// `fibrane law` through the real binary (FIBRANE_BIN, set by ctest): JSON keys, full precision,
// exit code 2 on bad input.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <string>

#include "laws/disk_sphere.hpp"
#include "laws/lennard_jones.hpp"

namespace {

struct Result {
  int exit_code;
  std::string output;
};

Result run_fibrane(const std::string& arguments) {
  const char* binary = std::getenv("FIBRANE_BIN");
  std::string command = std::string(binary) + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  char buffer[512];
  while (fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

double json_number(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\":");
  if (at == std::string::npos) throw std::runtime_error("missing key " + key + " in " + json);
  return std::strtod(json.c_str() + at + key.size() + 3, nullptr);
}

#define REQUIRE_BINARY() \
  if (!std::getenv("FIBRANE_BIN")) GTEST_SKIP() << "FIBRANE_BIN not set (run through ctest)"

TEST(LawCli, DiskHalfSpacePrintsEquation55InFullPrecision) {
  REQUIRE_BINARY();
  const Result r = run_fibrane("law disk-halfspace --m 6 --radius 0.8 --distance 1.3 --cos 0.6");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const double pi = std::numbers::pi, q = 1.3 * 1.3 - 0.48 * 0.48;
  // %.17g round-trips a double, so the printed value equals the closed form to rounding.
  EXPECT_NEAR(json_number(r.output, "value"), pi * pi * 0.64 / (6 * std::pow(q, 1.5)),
              1e-15 * json_number(r.output, "value"));
  for (const char* key : {"d_distance", "d_cos", "d2_distance", "d2_cos", "d2_distance_cos", "reduced_d_cos"})
    EXPECT_NO_THROW(json_number(r.output, key)) << key;
  EXPECT_NEAR(json_number(r.output, "reduced_d_cos") * 0.6, json_number(r.output, "d_cos"), 1e-15);
}

TEST(LawCli, LennardJonesMatchesTheLibrary) {
  REQUIRE_BINARY();
  const Result r = run_fibrane(
      "law lj-disk-plate --radius 1 --thickness 0.2 --distance 1.2 --cos 0.9 --epsilon 2 --sigma 0.1 "
      "--density-beam 3 --strength 0.5");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fibrane::laws::LennardJonesDiskPlate lj{2, 0.1, 1, 0.2, 3, 1, 0.5};
  const auto v = lj.evaluate(1.2, 0.9);
  EXPECT_DOUBLE_EQ(json_number(r.output, "value"), v.value);
  EXPECT_DOUBLE_EQ(json_number(r.output, "d2_distance_cos"), v.d_dc);
}

TEST(LawCli, DiskSphereMatchesTheLibrary) {
  REQUIRE_BINARY();
  const Result r = run_fibrane("law disk-sphere --radius 1 --sphere-radius 2 --distance 3.5");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_DOUBLE_EQ(json_number(r.output, "d_distance"), fibrane::laws::disk_sphere(1, 2, 3.5).d1);
}

TEST(LawCli, BadArgumentsExitWithCodeTwoAndAMessage) {
  REQUIRE_BINARY();
  for (const char* args : {"law disk-plate --m 12 --radius 1 --thickness 1 --distance 1 --cos 1",
                           "law disk-halfspace --m 2 --radius 1 --distance 3 --cos 1",
                           "law disk-halfspace --m 6 --radius 1 --distance 3 --cos 1.5",
                           "law disk-sphere --radius 1 --sphere-radius 1 --distance 1.5",
                           "law lj-disk-plate --radius 1 --thickness 1 --distance 3 --cos 1 --epsilon -1 --sigma 1",
                           "law disk-plate --radius 1"}) {
    const Result r = run_fibrane(args);
    EXPECT_EQ(r.exit_code, 2) << args;
    EXPECT_FALSE(r.output.empty()) << args;
  }
}

TEST(LawCli, NonFiniteArgumentsAreBadInputAndNonFiniteResultsAnError) {
  REQUIRE_BINARY();
  for (const char* args : {"law disk-halfspace --m nan --radius 1 --distance 3 --cos 1",
                           "law disk-plate --m 8 --radius inf --thickness 1 --distance 3 --cos 1",
                           "law disk-sphere --radius 1 --sphere-radius 1 --distance inf"}) {
    const Result r = run_fibrane(args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
    EXPECT_NE(r.output.find("must be a finite number"), std::string::npos) << r.output;
  }
  // Finite arguments whose result overflows or is undefined in double precision: exit 1 and a message,
  // never a JSON line with nan in it.
  for (const char* args : {"law disk-plate --m 8 --radius 1e-200 --thickness 1e200 --distance 1e200 --cos 1",
                           "law disk-sphere --radius 1e300 --sphere-radius 1e300 --distance 1e308",
                           "law disk-halfspace --m 50 --radius 1 --distance 1e-300 --cos 0"}) {
    const Result r = run_fibrane(args);
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.output;
    EXPECT_EQ(r.output.find("nan"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("outside the range where it can be evaluated"), std::string::npos) << r.output;
  }
}

}  // namespace
