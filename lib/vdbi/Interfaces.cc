// SPDX-License-Identifier: Apache-2.0

#include <vdbi/Interfaces.h>

#include <vdbi/CriticalElements.h>
#include <vdbi/Fattening.h>
#include <vdbi/InterfaceExtraction.h>
#include <vdbi/LabelGrid.h>
#include <vdbi/Remeshing.h>

#include <openvdb/Exceptions.h>

#include <chrono>
#include <cmath>
#include <string>

namespace vdbi {

namespace {

/// Times the stages of one run into Statistics::stageSeconds and tells the interrupter
/// (start/end, OpenVDB's convention) which stage runs, so that a progress display can say it.
class StageClock
{
public:
    StageClock(Statistics& stats, openvdb::util::NullInterrupter* interrupter)
        : mStats(stats), mInterrupter(interrupter) {}
    void start(const char* stage)
    {
        if (mInterrupter) mInterrupter->start(stage);
        mStage = stage;
        mStart = Clock::now();
    }
    void stop()
    {
        mStats.stageSeconds.emplace_back(mStage,
            std::chrono::duration<double>(Clock::now() - mStart).count());
        if (mInterrupter) mInterrupter->end();
    }

private:
    using Clock = std::chrono::steady_clock;
    Statistics& mStats;
    openvdb::util::NullInterrupter* mInterrupter;
    const char* mStage = "";
    Clock::time_point mStart;
};

/// The labels of @a region and a halo of Options::HALO voxels around it, background beyond.
/// @details Clipping makes critical elements at the halo's outer edge that the whole grid
/// does not have; their fattening reaches one voxel, and the faces owned by @a region read
/// labels and subdivision flags at most one voxel outside it, so a halo of 3 keeps them
/// out of sight. Only the leaves that meet the halo box are copied.
openvdb::Int32Grid::ConstPtr
labelsAround(const openvdb::Int32Grid& grid, const openvdb::CoordBBox& region)
{
    openvdb::CoordBBox box = region;
    box.expand(Options::HALO);
    const openvdb::Int32Grid::ConstPtr voxels = voxelizedLabels(grid);
    openvdb::Int32Grid::Ptr part = openvdb::Int32Grid::create(grid.background());
    part->setTransform(grid.transform().copy());
    std::vector<const openvdb::Int32Tree::LeafNodeType*> leaves;
    voxels->tree().getNodes(leaves);
    for (const auto* leaf : leaves) {
        if (box.hasOverlap(leaf->getNodeBoundingBox())) {
            part->tree().addLeaf(new openvdb::Int32Tree::LeafNodeType(*leaf));
        }
    }
    part->tree().clip(box);
    return part;
}

void
validate(const Options& options)
{
    if (!std::isfinite(options.edgeLength) || options.edgeLength < 0.0) {
        OPENVDB_THROW(openvdb::ValueError, "edge length must be a finite number > 0 (0 for "
            "one voxel), not " << options.edgeLength);
    }
    if (options.iterations < 0) {
        OPENVDB_THROW(openvdb::ValueError, "iterations must be >= 0, not "
            << options.iterations);
    }
    if (options.remesh && !options.region.empty()) {
        OPENVDB_THROW(openvdb::ValueError, "a region is extracted raw (remesh off): remeshed "
            "tiles would not stitch");
    }
    validateConstraints(options.repair.constraints);
}

} // namespace

Result
extractInterfaces(const openvdb::Int32Grid& grid, const Options& options)
{
    validate(options);
    Result result;
    Statistics& stats = result.statistics;
    StageClock clock(stats, options.repair.interrupter);

    // The repaired labels and what led to them go before remeshing, which needs only the
    // mesh (the fine grid of the frog: 70 MB).
    {
        clock.start("prepare");
        const openvdb::Int32Grid::ConstPtr labels = options.region.empty()
            ? voxelizedLabels(grid) : labelsAround(grid, options.region);
        stats.labelCount = collectLabels(*labels, options.repair.threaded).size();
        clock.stop();

        clock.start("critical elements");

        const CriticalElements elements = findCriticalElements(*labels, options.repair);
        stats.criticalFaces = elements.faces.size();
        stats.criticalEdges = elements.edges.size();
        stats.criticalVertices = elements.vertices.size();
        stats.singularVertices = elements.singularVertexCount();
        clock.stop();

        clock.start("fattening");

        const RefinedLabels refined = fattenCriticalElements(labels, elements, options.repair);
        stats.subdividedVoxels = refined.subdivided->activeVoxelCount();
        stats.relabelledSubvoxels = refined.fine->activeVoxelCount();
        stats.subdivision = refined.subdivision;
        clock.stop();

        clock.start("extraction");

        ExtractionOptions extraction;
        extraction.threaded = options.repair.threaded;
        extraction.ownerBox = options.region;
        extraction.pointKeys = options.pointKeys || !options.region.empty();
        extraction.interrupter = options.repair.interrupter;
        result.mesh = extractInterfacePatches(refined, extraction);
        clock.stop();
    }

    if (options.remesh) {
        clock.start("remeshing");
        RemeshOptions remeshing;
        const openvdb::Vec3d voxel = grid.voxelSize();
        remeshing.edgeLength = options.edgeLength > 0.0 ? options.edgeLength : voxel[0];
        remeshing.iterations = options.iterations;
        remeshing.voxelSize = voxel;
        remeshing.threaded = options.repair.threaded;
        remeshing.interrupter = options.repair.interrupter;
        RemeshStatistics remeshStats;
        result.mesh = remeshPatches(result.mesh, remeshing, &remeshStats);
        stats.meetingPairs = remeshStats.meetingPairs;
        stats.farFaceCentres = remeshStats.farFaceCentres;
        clock.stop();
    }

    stats.patches = result.mesh.patches.size();
    stats.triangles = result.mesh.triangles.size();
    stats.vertices = result.mesh.points.size();
    return result;
}

std::string
runWarning(const Statistics& statistics)
{
    std::string warning;
    if (statistics.meetingPairs > 0) {
        warning = std::to_string(statistics.meetingPairs) + " pairs of remeshed triangles "
            "cross or touch (the extracted patches, without remeshing, never do)";
    }
    if (statistics.farFaceCentres > 0) {
        if (!warning.empty()) warning += "; ";
        warning += std::to_string(statistics.farFaceCentres) + " voxel face centres lie "
            "farther than one voxel from their remeshed patch";
    }
    return warning;
}

} // namespace vdbi
