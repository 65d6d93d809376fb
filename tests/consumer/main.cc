// SPDX-License-Identifier: Apache-2.0
/// @file tests/consumer/main.cc
/// @brief Builds against the installed vdb_interfaces package: two face-adjacent voxels of
/// labels 1 and 2 on background 0 give the patches (0,1), (0,2) and (1,2).

#include <vdbi/Interfaces.h>

#include <openvdb/openvdb.h>

#include <cstdlib>
#include <exception>
#include <iostream>

int
main()
{
    try {
        openvdb::initialize();
        openvdb::Int32Grid grid(/*background=*/0);
        grid.tree().setValue(openvdb::Coord(0, 0, 0), 1);
        grid.tree().setValue(openvdb::Coord(1, 0, 0), 2);

        vdbi::Options options;
        options.remesh = false; // the raw extraction: its counts are exact
        const vdbi::Result result = vdbi::extractInterfaces(grid, options);
        const vdbi::InterfaceMesh& mesh = result.mesh;
        std::cout << "patches " << mesh.patches.size() << ", triangles "
                  << mesh.triangleCount() << ", vertices " << mesh.pointCount() << "\n";
        for (const vdbi::InterfacePatch& p : mesh.patches) {
            std::cout << "  patch " << p.a << " " << p.b << ": " << p.triangleCount
                      << " triangles\n";
        }
        if (mesh.patches.size() != 3 || mesh.triangleCount() != 22 || mesh.pointCount() != 12) {
            std::cerr << "vdbi_consumer: expected 3 patches, 22 triangles, 12 vertices\n";
            return EXIT_FAILURE;
        }
        return EXIT_SUCCESS;
    } catch (const std::exception& e) {
        std::cerr << "vdbi_consumer: " << e.what() << "\n";
        return EXIT_FAILURE;
    }
}
