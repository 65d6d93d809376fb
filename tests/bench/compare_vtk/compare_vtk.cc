// SPDX-License-Identifier: Apache-2.0
/// @file bench/compare_vtk/compare_vtk.cc
/// @brief The frog through VTK's vtkDiscreteFlyingEdges3D and through our repair + extraction,
/// in the same process and the same rounds, with TBB limited to 1 and to 2 threads.
/// @details The volume is read once (our reader); VTK gets the MetaImage's whole dense image
/// (500 x 470 x 136 unsigned chars, the file's own type, spacing and origin) and one contour
/// value per label but the background (as VTK's frog examples do). Ours starts from the sparse
/// grid: critical elements, fattening, extraction (and voxelizedLabels + collectLabels,
/// "prepare", reported beside). Debian's VTK 9.1 runs vtkSMPTools on TBB, so the same
/// tbb::global_control limits both. Rounds alternate the two and the thread counts after one
/// warm-up round; medians of the wall seconds.
///
/// Then, untimed: VTK's surfaces with the background contoured too (so every interface
/// should be meshed from both sides) are checked for mismatched edges: an edge of one label's
/// surface that no other label's surface has. In a consistent set of interfaces every edge
/// lies on at least two labels' surfaces. (vtkSurfaceNets3D, which meshes every interface
/// once, exists from VTK 9.3 on; Debian 12 ships 9.1.)
///
/// Usage: compare_vtk [--reps N]   (default 7)

#include "BenchSupport.h"
#include "support/TestData.h"

#include <vdbi/CriticalElements.h>
#include <vdbi/Fattening.h>
#include <vdbi/HugePages.h>
#include <vdbi/InterfaceExtraction.h>
#include <vdbi/LabelGrid.h>
#include <vdbi/LabelVolumeReader.h>
#include <vdbi/MetaImageReader.h>

#include <openvdb/openvdb.h>

#include <tbb/global_control.h>

#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkDiscreteFlyingEdges3D.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSMPTools.h>
#include <vtkVersion.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace {

using vdbi_bench::Clock;
using vdbi_bench::median;
using vdbi_bench::ratio;
using vdbi_bench::seconds;

/// The frog's dense image as VTK reads it: the MetaImage's extent, element type and geometry.
vtkSmartPointer<vtkImageData>
denseImage(const openvdb::Int32Grid& grid, const std::string& headerPath)
{
    std::ifstream in(headerPath);
    const vdbi::MetaImageHeader header = vdbi::parseMetaImageHeader(in, headerPath);
    if (header.elementType != vdbi::MetaElementType::UChar) {
        throw std::runtime_error("expected the frog's unsigned char image");
    }
    const auto& dim = header.dimSize;
    auto image = vtkSmartPointer<vtkImageData>::New();
    image->SetDimensions(dim[0], dim[1], dim[2]);
    image->SetSpacing(header.spacing[0], header.spacing[1], header.spacing[2]);
    image->SetOrigin(header.offset[0], header.offset[1], header.offset[2]);
    image->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
    auto* voxels = static_cast<unsigned char*>(image->GetScalarPointer());
    std::memset(voxels, 0, header.voxelCount());
    const openvdb::CoordBBox extent(openvdb::Coord(0),
        openvdb::Coord(dim[0] - 1, dim[1] - 1, dim[2] - 1));
    for (auto v = grid.cbeginValueOn(); v; ++v) {
        const openvdb::Coord& c = v.getCoord();
        if (!extent.isInside(c) || *v < 0 || *v > 255) {
            throw std::runtime_error("a voxel outside the image or its type");
        }
        voxels[(std::size_t(c.z()) * std::size_t(dim[1]) + std::size_t(c.y()))
            * std::size_t(dim[0]) + std::size_t(c.x())] = static_cast<unsigned char>(*v);
    }
    return image;
}

/// One vtkDiscreteFlyingEdges3D run over @a image with one value per label in @a labels.
vtkSmartPointer<vtkPolyData>
runVtk(vtkImageData* image, const std::vector<vdbi::Label>& labels)
{
    vtkNew<vtkDiscreteFlyingEdges3D> contour;
    contour->SetInputData(image);
    contour->ComputeNormalsOff();
    contour->ComputeGradientsOff();
    contour->ComputeScalarsOn(); // the label of every point: needed to tell surfaces apart
    contour->SetNumberOfContours(int(labels.size()));
    for (std::size_t i = 0; i < labels.size(); ++i) contour->SetValue(int(i), labels[i]);
    contour->Update();
    return contour->GetOutput();
}

/// Sizes of our result.
struct OurRun
{
    double prepare = 0, repairExtraction = 0;
    std::size_t labels = 0, triangles = 0;
};

OurRun
runOurs(const openvdb::Int32Grid& grid)
{
    OurRun r;
    const vdbi::RepairOptions options;
    const auto t0 = Clock::now();
    const openvdb::Int32Grid::ConstPtr labels = vdbi::voxelizedLabels(grid);
    r.labels = vdbi::collectLabels(*labels).size();
    const auto t1 = Clock::now();
    const vdbi::CriticalElements elements = vdbi::findCriticalElements(*labels, options);
    const vdbi::RefinedLabels refined = vdbi::fattenCriticalElements(labels, elements, options);
    const vdbi::InterfaceMesh mesh = vdbi::extractInterfacePatches(refined);
    const auto t2 = Clock::now();
    r.prepare = seconds(t0, t1);
    r.repairExtraction = seconds(t1, t2);
    r.triangles = mesh.triangles.size();
    return r;
}

/// Edges of every label's surface (VTK keeps a point set per contour value), each counted
/// once per label: the number of edges, and of those no other label's surface has.
struct EdgeMatch
{
    std::size_t edges = 0, unmatched = 0;
};

EdgeMatch
countUnmatchedEdges(vtkPolyData* surfaces, const std::array<double, 3>& spacing,
                    const std::array<double, 3>& origin)
{
    // Points lie on voxel-centre midpoints: twice the index coordinate is an integer.
    using Key = std::array<std::int64_t, 3>;
    auto keyOf = [&](vtkIdType p) {
        double x[3];
        surfaces->GetPoint(p, x);
        Key k;
        for (int a = 0; a < 3; ++a) {
            k[std::size_t(a)] = std::llround(2.0 * (x[a] - origin[std::size_t(a)])
                / spacing[std::size_t(a)]);
        }
        return k;
    };
    struct EdgeHash
    {
        std::size_t operator()(const std::array<std::int64_t, 6>& e) const
        {
            std::size_t h = 1469598103934665603ull;
            for (std::int64_t v : e) h = (h ^ std::size_t(v)) * 1099511628211ull;
            return h;
        }
    };
    // Per edge: the first label seen on it, and whether another label has it too.
    std::unordered_map<std::array<std::int64_t, 6>, std::pair<double, bool>, EdgeHash> edges;
    vtkDataArray* labels = surfaces->GetPointData()->GetScalars();
    vtkCellArray* polys = surfaces->GetPolys();
    const vtkIdType cells = polys->GetNumberOfCells();
    std::vector<std::pair<double, std::array<std::int64_t, 6>>> labelledEdges;
    labelledEdges.reserve(std::size_t(cells) * 3);
    vtkIdType n = 0;
    const vtkIdType* ids = nullptr;
    for (polys->InitTraversal(); polys->GetNextCell(n, ids);) {
        const double label = labels->GetTuple1(ids[0]);
        for (vtkIdType i = 0; i < n; ++i) {
            Key a = keyOf(ids[i]), b = keyOf(ids[(i + 1) % n]);
            if (b < a) std::swap(a, b);
            labelledEdges.push_back({label, {a[0], a[1], a[2], b[0], b[1], b[2]}});
        }
    }
    // Each label's edges once (an inner edge is in two of its triangles).
    std::sort(labelledEdges.begin(), labelledEdges.end());
    labelledEdges.erase(std::unique(labelledEdges.begin(), labelledEdges.end()),
        labelledEdges.end());
    for (const auto& [label, edge] : labelledEdges) {
        auto [it, isNew] = edges.try_emplace(edge, label, false);
        if (!isNew && it->second.first != label) it->second.second = true;
    }
    EdgeMatch m;
    m.edges = labelledEdges.size();
    for (const auto& le : labelledEdges) {
        if (!edges.at(le.second).second) ++m.unmatched;
    }
    return m;
}

} // namespace

int
main(int argc, char** argv)
{
    vdbi::restartWithHugePages(argv); // as the CLI does: see HugePages.h
    int reps = 7;
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "--reps" && i + 1 < argc) reps = std::max(1, std::atoi(argv[++i]));
        else {
            std::fprintf(stderr, "usage: %s [--reps N]\n", argv[0]);
            return 2;
        }
    }
    openvdb::initialize();
    const std::string path = vdbi_test::dataPath("frogtissue.mhd");
    const openvdb::Int32Grid::Ptr grid = vdbi::readLabelVolume(path);
    const vtkSmartPointer<vtkImageData> image = denseImage(*grid, path);
    std::vector<vdbi::Label> labels = vdbi::collectLabels(*vdbi::voxelizedLabels(*grid));
    std::vector<vdbi::Label> contoured;
    for (vdbi::Label l : labels) if (l != grid->background()) contoured.push_back(l);

    int dims[3];
    image->GetDimensions(dims);
    std::printf("compare_vtk: frogtissue.mhd, %lld labelled voxels in a %d x %d x %d image "
        "(%.1f M voxels); VTK %s, vtkSMPTools backend %s\n", (long long)grid->activeVoxelCount(),
        dims[0], dims[1], dims[2], 1e-6 * double(dims[0]) * dims[1] * dims[2],
        vtkVersion::GetVTKVersion(), vtkSMPTools::GetBackend());
    std::printf("vtkDiscreteFlyingEdges3D with %zu contour values (every label but the "
        "background; normals, gradients off, scalars on) vs our repair + extraction\n"
        "load average before: %s; heap: %s\n", contoured.size(),
        vdbi_bench::loadAverage().c_str(), vdbi_bench::heapPages().c_str());

    const int threadCounts[] = {1, 2};
    // Wall seconds of VTK, of our repair + extraction and of our prepare; CPU seconds (all
    // threads) of VTK and of ours (prepare included), which show how many threads worked.
    std::array<std::vector<double>, 2> vtkSeconds, ourSeconds, ourPrepare, vtkCpu, ourCpu;
    std::size_t vtkTriangles = 0, vtkPoints = 0, ourTriangles = 0;
    const double cpu0 = vdbi_bench::cpuSeconds();
    const auto wall0 = Clock::now();
    for (int rep = -1; rep < reps; ++rep) { // rep -1: warm-up
        for (std::size_t t = 0; t < 2; ++t) {
            tbb::global_control control(tbb::global_control::max_allowed_parallelism,
                std::size_t(threadCounts[t]));
            // Alternate which goes first, so that neither always runs on the other's heap.
            for (int k = 0; k < 2; ++k) {
                const double c0 = vdbi_bench::cpuSeconds();
                if ((k == 0) == (rep % 2 == 0)) {
                    const auto t0 = Clock::now();
                    const vtkSmartPointer<vtkPolyData> out = runVtk(image, contoured);
                    const double s = seconds(t0, Clock::now());
                    vtkTriangles = std::size_t(out->GetNumberOfPolys());
                    vtkPoints = std::size_t(out->GetNumberOfPoints());
                    if (rep >= 0) {
                        vtkSeconds[t].push_back(s);
                        vtkCpu[t].push_back(vdbi_bench::cpuSeconds() - c0);
                    }
                } else {
                    const OurRun r = runOurs(*grid);
                    ourTriangles = r.triangles;
                    if (rep >= 0) {
                        ourSeconds[t].push_back(r.repairExtraction);
                        ourPrepare[t].push_back(r.prepare);
                        ourCpu[t].push_back(vdbi_bench::cpuSeconds() - c0);
                    }
                }
            }
        }
    }
    const double cpu = vdbi_bench::cpuSeconds() - cpu0;
    const double wall = seconds(wall0, Clock::now());

    std::printf("\nmedian wall seconds of %d rounds (after a warm-up round)\n", reps);
    std::printf("%8s %10s %12s %12s %10s %14s | %10s %14s\n", "threads", "VTK s",
        "ours s", "ours+prep s", "VTK/ours", "VTK/ours+prep", "VTK CPU s", "ours+prep CPU");
    for (std::size_t t = 0; t < 2; ++t) {
        const double v = median(vtkSeconds[t]);
        const double o = median(ourSeconds[t]);
        const double p = median(ourPrepare[t]);
        std::printf("%8d %10.4f %12.4f %12.4f %10.2f %14.2f | %10.4f %14.4f\n",
            threadCounts[t], v, o, o + p, ratio(v, o), ratio(v, o + p), median(vtkCpu[t]),
            median(ourCpu[t]));
    }
    std::printf("(the target: VTK/ours >= 6)\n");
    std::printf("VTK: %zu triangles, %zu points (every interface twice, once per side); ours: "
        "%zu triangles (every interface once, repaired)\n", vtkTriangles, vtkPoints,
        ourTriangles);
    std::printf("timed rounds: %.1f s wall, %.1f s CPU; load average after: %s\n", wall, cpu,
        vdbi_bench::loadAverage().c_str());

    // Untimed: VTK's surfaces with the background contoured too.
    double spacing[3], origin[3];
    image->GetSpacing(spacing);
    image->GetOrigin(origin);
    const vtkSmartPointer<vtkPolyData> all = runVtk(image, labels);
    const EdgeMatch m = countUnmatchedEdges(all, {spacing[0], spacing[1], spacing[2]},
        {origin[0], origin[1], origin[2]});
    std::printf("\nVTK with the background contoured too (%zu values, %lld triangles): of %zu "
        "edges (each label's once), %zu are on no other label's surface (mismatched)\n",
        labels.size(), (long long)all->GetNumberOfPolys(), m.edges, m.unmatched);
    std::printf("(vtkSurfaceNets3D, one mesh per interface, needs VTK >= 9.3; this is %s)\n",
        vtkVersion::GetVTKVersion());
    return 0;
}
