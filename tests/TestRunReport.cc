// SPDX-License-Identifier: Apache-2.0
/// @file TestRunReport.cc
/// @brief The report of a run: the JSON parses back to what was written (odd file names
/// included), the text has every line.

#include <vdbi/RunReport.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sstream>

namespace {

vdbi::RunReport
sampleReport(const std::string& input)
{
    vdbi::RunReport report;
    report.program = "vdb_interfaces";
    report.version = "1.2.3";
    report.input = input;
    report.statistics.labelCount = 22;
    report.statistics.criticalFaces = 1;
    report.statistics.criticalEdges = 121;
    report.statistics.criticalVertices = 173;
    report.statistics.singularVertices = 8;
    report.statistics.subdivision = 5;
    report.statistics.subdividedVoxels = 566;
    report.statistics.relabelledSubvoxels = 5490;
    report.statistics.patches = 68;
    report.statistics.triangles = 35120;
    report.statistics.vertices = 16475;
    report.statistics.meetingPairs = 3;
    report.statistics.farFaceCentres = 2;
    report.stages = {{"read", 0.25}, {"extraction", 1.5e-7}, {"write", 3.0}};
    report.totalSeconds = 4.75;
    report.peakMemoryBytes = 5'000'000'000ull; // beyond 32 bits
    return report;
}

} // namespace

TEST(TestRunReport, testRunWarning)
{
    vdbi::Statistics stats;
    EXPECT_EQ(vdbi::runWarning(stats), "");
    stats.meetingPairs = 4;
    EXPECT_EQ(vdbi::runWarning(stats).rfind("4 pairs of remeshed triangles cross or touch", 0),
              0u) << vdbi::runWarning(stats);
    EXPECT_EQ(vdbi::runWarning(stats).find("face centres"), std::string::npos);
    // Both promises broken: one message naming both.
    stats.farFaceCentres = 7;
    const std::string both = vdbi::runWarning(stats);
    EXPECT_EQ(both.rfind("4 pairs of remeshed triangles cross or touch", 0), 0u) << both;
    EXPECT_NE(both.find("; 7 voxel face centres lie farther than one voxel from their remeshed "
                        "patch"), std::string::npos) << both;
    stats.meetingPairs = 0;
    EXPECT_EQ(vdbi::runWarning(stats).rfind("7 voxel face centres lie farther than one voxel", 0),
              0u) << vdbi::runWarning(stats);
}

TEST(TestRunReport, testJsonReadsBack)
{
    const std::string input = "dir/with \"quotes\"\\back\tslash\nand\x01" "control.vox";
    std::ostringstream os;
    vdbi::writeRunReportJson(os, sampleReport(input));
    const std::string text = os.str();
    ASSERT_EQ(text.back(), '\n');

    const nlohmann::json json = nlohmann::json::parse(text);
    EXPECT_EQ(json.at("program"), "vdb_interfaces");
    EXPECT_EQ(json.at("version"), "1.2.3");
    EXPECT_EQ(json.at("input"), input);
    EXPECT_EQ(json.at("labels"), 22);
    EXPECT_EQ(json.at("critical_faces"), 1);
    EXPECT_EQ(json.at("critical_edges"), 121);
    EXPECT_EQ(json.at("critical_vertices"), 173);
    EXPECT_EQ(json.at("singular_vertices"), 8);
    EXPECT_EQ(json.at("subdivision"), 5);
    EXPECT_EQ(json.at("subdivided_voxels"), 566);
    EXPECT_EQ(json.at("relabelled_subvoxels"), 5490);
    EXPECT_EQ(json.at("patches"), 68);
    EXPECT_EQ(json.at("triangles"), 35120);
    EXPECT_EQ(json.at("vertices"), 16475);
    EXPECT_EQ(json.at("meeting_triangle_pairs"), 3);
    EXPECT_EQ(json.at("far_voxel_face_centres"), 2);
    ASSERT_EQ(json.at("stages").size(), 3u);
    EXPECT_EQ(json.at("stages")[0].at("name"), "read");
    EXPECT_EQ(json.at("stages")[1].at("name"), "extraction");
    EXPECT_EQ(json.at("stages")[1].at("seconds").get<double>(), 1.5e-7);
    EXPECT_EQ(json.at("stages")[2].at("seconds").get<double>(), 3.0);
    EXPECT_EQ(json.at("total_seconds").get<double>(), 4.75);
    EXPECT_EQ(json.at("peak_memory_bytes").get<std::uint64_t>(), 5'000'000'000ull);
}

TEST(TestRunReport, testInvalidUtf8NameStillGivesJson)
{
    // File names are bytes; a name that is not UTF-8 must not make the report fail.
    std::ostringstream os;
    vdbi::writeRunReportJson(os, sampleReport("bad\xff\xfename.vox"));
    const nlohmann::json json = nlohmann::json::parse(os.str());
    const std::string input = json.at("input");
    EXPECT_EQ(input.rfind("bad", 0), 0u);
    EXPECT_NE(input.find("name.vox"), std::string::npos);
}

TEST(TestRunReport, testTextHasEveryLine)
{
    std::ostringstream os;
    os.precision(9);
    vdbi::printRunReport(os, sampleReport("x.vox"));
    const std::string text = os.str();
    for (const std::string line : {"labels                22\n", "critical edges        121\n",
             "singular vertices     8\n", "relabelled subvoxels  5490\n",
             "triangles             35120\n", "far face centres      2\n", "seconds\n", "  read                0.250\n",
             "  write               3.000\n", "  total               4.750\n",
             "peak memory           4768.4 MiB\n"})
    {
        EXPECT_NE(text.find(line), std::string::npos) << line << " in\n" << text;
    }
    EXPECT_EQ(os.precision(), 9) << "the stream's format is restored";
}

TEST(TestRunReport, testPeakMemoryIsKnown)
{
    EXPECT_GT(vdbi::peakResidentMemoryBytes(), 1u << 20);
}
