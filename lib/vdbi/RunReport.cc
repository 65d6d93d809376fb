// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/RunReport.cc

#include <vdbi/RunReport.h>

#include <nlohmann/json.hpp>

#include <sys/resource.h> // getrusage

#include <iomanip>
#include <ostream>

namespace vdbi {

namespace {

/// The counts in the order they are printed: label for people, JSON key, value.
struct Count
{
    const char* label;
    const char* key;
    std::uint64_t value;
};

std::vector<Count>
countsOf(const Statistics& st)
{
    return {{"labels", "labels", st.labelCount},
        {"critical faces", "critical_faces", st.criticalFaces},
        {"critical edges", "critical_edges", st.criticalEdges},
        {"critical vertices", "critical_vertices", st.criticalVertices},
        {"singular vertices", "singular_vertices", st.singularVertices},
        {"subdivision", "subdivision", static_cast<std::uint64_t>(st.subdivision)},
        {"subdivided voxels", "subdivided_voxels", st.subdividedVoxels},
        {"relabelled subvoxels", "relabelled_subvoxels", st.relabelledSubvoxels},
        {"patches", "patches", st.patches},
        {"triangles", "triangles", st.triangles},
        {"vertices", "vertices", st.vertices},
        {"meeting pairs", "meeting_triangle_pairs", st.meetingPairs},
        {"far face centres", "far_voxel_face_centres", st.farFaceCentres}};
}

} // namespace

std::uint64_t
peakResidentMemoryBytes()
{
    struct rusage usage;
    if (::getrusage(RUSAGE_SELF, &usage) != 0) return 0;
    return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024u; // Linux: KiB
}

void
printRunReport(std::ostream& os, const RunReport& report)
{
    const std::ios::fmtflags flags = os.flags();
    const std::streamsize precision = os.precision();
    os << std::left;
    for (const Count& count : countsOf(report.statistics)) {
        os << std::setw(22) << count.label << count.value << "\n";
    }
    os << "seconds\n" << std::fixed << std::setprecision(3);
    for (const auto& [name, seconds] : report.stages) {
        os << "  " << std::setw(20) << name << seconds << "\n";
    }
    os << "  " << std::setw(20) << "total" << report.totalSeconds << "\n";
    os << std::setw(22) << "peak memory" << std::setprecision(1)
       << double(report.peakMemoryBytes) / (1024.0 * 1024.0) << " MiB\n";
    os.flags(flags);
    os.precision(precision);
}

void
writeRunReportJson(std::ostream& os, const RunReport& report)
{
    // ordered_json keeps the keys in the order written, so the file reads top-down.
    nlohmann::ordered_json json;
    json["program"] = report.program;
    json["version"] = report.version;
    json["input"] = report.input;
    for (const Count& count : countsOf(report.statistics)) json[count.key] = count.value;
    json["stages"] = nlohmann::ordered_json::array();
    for (const auto& [name, seconds] : report.stages) {
        json["stages"].push_back({{"name", name}, {"seconds", seconds}});
    }
    json["total_seconds"] = report.totalSeconds;
    json["peak_memory_bytes"] = report.peakMemoryBytes;
    // Invalid UTF-8 in a file name is replaced rather than thrown on.
    os << json.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace) << "\n";
}

} // namespace vdbi
