// SPDX-License-Identifier: Apache-2.0
/// @file vdbi/RunReport.h
/// @brief What a run found and how long it took, as text for people and JSON for scripts:
/// the CLI's --stats and --report, and what a host application may show.

#ifndef VDBI_RUN_REPORT_HAS_BEEN_INCLUDED
#define VDBI_RUN_REPORT_HAS_BEEN_INCLUDED

#include <vdbi/Interfaces.h>

#include <cstdint>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

namespace vdbi {

/// One run of a tool around extractInterfaces().
struct RunReport
{
    std::string program;  ///< the tool, e.g. "vdb_interfaces"
    std::string version;
    std::string input;    ///< the file read
    Statistics statistics;
    /// Seconds per stage in the order they ran: reading, the pipeline's stages, writing.
    std::vector<std::pair<std::string, double>> stages;
    double totalSeconds = 0.0;
    std::uint64_t peakMemoryBytes = 0;
};

/// Peak resident memory of this process so far, in bytes (0 where unknown).
std::uint64_t peakResidentMemoryBytes();

/// Aligned "name value" lines: the counts, the seconds per stage, the peak memory.
void printRunReport(std::ostream& os, const RunReport& report);

/// A JSON object: program, version, input, the counts (labels, critical_faces, ...,
/// triangles, vertices), stages [{name, seconds}], total_seconds, peak_memory_bytes.
void writeRunReportJson(std::ostream& os, const RunReport& report);

} // namespace vdbi

#endif // VDBI_RUN_REPORT_HAS_BEEN_INCLUDED
