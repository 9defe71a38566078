// The cause tools' --json output (bench/common/json_output.h): the text lands whole, or the tool
// says why on stderr and exits with status 2, leaving nothing behind.
#include "json_output.h"
#include "test_support.h"

#include <gtest/gtest.h>

#include <filesystem>

using namespace ffd;
using namespace ffd::test;
namespace fs = std::filesystem;

TEST(JsonOutput, TheTextLandsWholeAndTheStatusIsZero) {
    TempDir dir;
    AtomicFile file(dir / "out.json", "w");
    testing::internal::CaptureStderr();
    EXPECT_EQ(bench::commitJson(file, "{\"a\": 1}\n", "tool"), 0);
    EXPECT_EQ(testing::internal::GetCapturedStderr(), "");
    EXPECT_EQ(readFile(dir / "out.json"), "{\"a\": 1}\n");
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator{}), 1);
}

TEST(JsonOutput, AFailedCommitNamesTheToolTheFlagAndThePathAndGivesStatusTwo) {
    // The folder was there when the tool started and is gone when the table is written: the
    // finished file cannot be renamed into place.
    TempDir dir;
    fs::create_directories(dir / "out");
    AtomicFile file(dir / "out" / "table.json", "w");
    fs::remove_all(dir / "out");
    testing::internal::CaptureStderr();
    EXPECT_EQ(bench::commitJson(file, "{}\n", "ffdaabb_energy_stages"), 2);
    const std::string err = testing::internal::GetCapturedStderr();
    EXPECT_NE(err.find("ffdaabb_energy_stages: --json: "), std::string::npos) << err;
    EXPECT_NE(err.find("table.json"), std::string::npos) << err;
    EXPECT_FALSE(fs::exists(dir / "out"));
}
