// SPDX-License-Identifier: Apache-2.0
/// @file houdini/SOP_VDBInterfaces.cc
/// @brief The "VDB Interfaces" SOP (token vdbinterfaces).
/// @details Only HDK calls live here: reading the parameters and the input VDB, and copying
/// the library's arrays into the output detail. Parsing, the pipeline and the array layout are
/// in lib/ (vdbi/GeometryArrays.h, vdbi/Interfaces.h), where they are unit-tested.
/// @note Never compiled on the machine it was written on (no HDK there); see README.md.

#include "SOP_VDBInterfaces.h"

#include <vdbi/Exceptions.h>
#include <vdbi/GeometryArrays.h>
#include <vdbi/Interfaces.h>
#include <vdbi/Types.h>

#include <houdini_utils/ParmFactory.h>
#include <openvdb_houdini/SOP_NodeVDB.h>
#include <openvdb_houdini/Utils.h>  // for VdbPrimCIterator

#include <openvdb/openvdb.h>
#include <openvdb/util/NullInterrupter.h>
#include <openvdb/version.h>

#include <GA/GA_Defaults.h>
#include <GA/GA_Detail.h>    // for GA_Detail::OffsetMarker
#include <GA/GA_Handle.h>
#include <GA/GA_Iterator.h>
#include <GA/GA_Range.h>
#include <GA/GA_Types.h>
#include <GEO/GEO_PolyCounts.h>
#include <GU/GU_Detail.h>
#include <GU/GU_PrimPoly.h>
#include <GU/GU_PrimVDB.h>
#include <OP/OP_AutoLockInputs.h>
#include <OP/OP_Operator.h>
#include <OP/OP_OperatorTable.h>
#include <PRM/PRM_Include.h>
#include <UT/UT_Interrupt.h>
#include <UT/UT_VDBUtils.h>  // for UT_VDB_INT32, UTvdbType
#include <UT/UT_Vector3.h>

#include <cstddef>
#include <exception>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

// The library polls a polymorphic openvdb::util::NullInterrupter (OpenVDB 10 and later).
static_assert(OPENVDB_LIBRARY_MAJOR_VERSION_NUMBER >= 10,
    "VDB Interfaces needs OpenVDB 10 or later: Houdini 20.0 or later");

namespace hvdb = openvdb_houdini;
namespace hutil = houdini_utils;

namespace vdbi_houdini {

namespace {

/// Forwards the library's polls (between passes and per chunk of leaves, from TBB worker
/// threads too) to Houdini's interrupt: Esc in the viewport stops the cook.
class CookInterrupter final : public openvdb::util::NullInterrupter
{
public:
    explicit CookInterrupter(const char* title) : mProgress(title) {}

    bool wasInterrupted(int percent = -1) override
    {
        return percent < 0 ? mProgress.wasInterrupted() : mProgress.wasInterrupted(percent);
    }

private:
    UT_AutoInterrupt mProgress;
};

/// The first int32 VDB primitive among @a group (all VDBs if null), or null. @a others
/// collects "'name' (type)" of the VDBs of other types; @a int32Count counts the int32 ones.
const GU_PrimVDB*
findLabelVdb(const GU_Detail& input, const GA_PrimitiveGroup* group,
    std::vector<std::string>& others, std::size_t& int32Count)
{
    const GU_PrimVDB* found = nullptr;
    int32Count = 0;
    for (hvdb::VdbPrimCIterator it(&input, group); it; ++it) {
        const GU_PrimVDB* vdb = it.getPrimitive();
        if (vdb->getStorageType() == UT_VDB_INT32) {
            if (!found) found = vdb;
            ++int32Count;
        } else {
            others.push_back("'" + it.getPrimitiveNameOrIndex().toStdString() + "' ("
                + UTvdbType(vdb->getStorageType()) + ")");
        }
    }
    return found;
}

/// Copies the library's arrays into @a detail: one block of points, one block of triangles,
/// then the primitive attributes over the new primitives, in triangle order.
void
writeGeometry(GU_Detail& detail, const vdbi::GeometryArrays& arrays)
{
    const GA_Size pointCount = GA_Size(arrays.pointCount());
    if (pointCount == 0) return;

    const GA_Offset startPoint = detail.appendPointBlock(pointCount);
    static_assert(sizeof(UT_Vector3F) == 3 * sizeof(float), "UT_Vector3F is three floats");
    GA_RWHandleV3 positions(detail.getP());
    positions.setBlock(startPoint, pointCount,
        reinterpret_cast<const UT_Vector3F*>(arrays.points.data()));

    // Runs of equal sizes (all 3 today).
    GEO_PolyCounts polyCounts;
    for (std::size_t i = 0; i < arrays.polyCounts.size();) {
        std::size_t j = i + 1;
        while (j < arrays.polyCounts.size() && arrays.polyCounts[j] == arrays.polyCounts[i]) ++j;
        polyCounts.append(arrays.polyCounts[i], GA_Size(j - i));
        i = j;
    }

    GA_Detail::OffsetMarker marker(detail);
    GU_PrimPoly::buildBlock(&detail, startPoint, pointCount, polyCounts,
        arrays.vertices.data());
    const GA_Range primitives(marker.primitiveRange());

    GA_RWHandleI labelA(detail.addIntTuple(
        GA_ATTRIB_PRIMITIVE, "label_a", 1, GA_Defaults(-1)).getAttribute());
    GA_RWHandleI labelB(detail.addIntTuple(
        GA_ATTRIB_PRIMITIVE, "label_b", 1, GA_Defaults(-1)).getAttribute());
    GA_RWHandleI patch(detail.addIntTuple(
        GA_ATTRIB_PRIMITIVE, "patch", 1, GA_Defaults(-1)).getAttribute());
    GA_RWHandleS name(detail.addStringTuple(GA_ATTRIB_PRIMITIVE, "name", 1).getAttribute());
    if (!labelA.isValid() || !labelB.isValid() || !patch.isValid() || !name.isValid()) {
        throw std::runtime_error("could not create the primitive attributes");
    }

    std::size_t i = 0;
    for (GA_Iterator it(primitives); !it.atEnd() && i < arrays.primitiveCount(); ++it, ++i) {
        const GA_Offset offset = it.getOffset();
        labelA.set(offset, arrays.labelA[i]);
        labelB.set(offset, arrays.labelB[i]);
        patch.set(offset, arrays.patch[i]);
        name.set(offset, 0, arrays.patchNames[std::size_t(arrays.patch[i])].c_str());
    }
    if (i != arrays.primitiveCount()) {
        throw std::runtime_error("built " + std::to_string(i) + " primitives, expected "
            + std::to_string(arrays.primitiveCount()));
    }
}

} // namespace


OP_Node*
SOP_VDBInterfaces::factory(OP_Network* net, const char* name, OP_Operator* op)
{
    return new SOP_VDBInterfaces(net, name, op);
}


SOP_VDBInterfaces::SOP_VDBInterfaces(OP_Network* net, const char* name, OP_Operator* op)
    : hvdb::SOP_NodeVDB(net, name, op)
{
}


bool
SOP_VDBInterfaces::updateParmsFlags()
{
    const bool remesh = evalInt("remesh", 0, 0) != 0;
    bool changed = false;
    changed |= enableParm("edgelength", remesh);
    changed |= enableParm("iterations", remesh);
    return changed;
}


OP_ERROR
SOP_VDBInterfaces::cookVDBSop(OP_Context& context)
{
    try {
        OP_AutoLockInputs inputs(this);
        if (inputs.lock(context) >= UT_ERROR_ABORT) return error();
        gdp->clearAndDestroy();

        // Parameters, read once.
        const fpreal time = context.getTime();
        const std::string groupPattern = evalStdString("group", time);
        vdbi::Options options;
        options.remesh = evalInt("remesh", 0, time) != 0;
        options.pointKeys = false; // for stitching tiles; the geometry does not use them
        options.edgeLength = double(evalFloat("edgelength", 0, time));
        options.iterations = int(evalInt("iterations", 0, time));
        options.repair.constraints = vdbi::parseConstraints(evalStdString("constraints", time));
        options.repair.priority =
            vdbi::LabelPriority(vdbi::parseLabels(evalStdString("priority", time)));

        // The label VDB: the first int32 VDB of the group.
        const GU_Detail* input = inputGeo(0, context);
        const GA_PrimitiveGroup* group = matchGroup(*input, groupPattern);
        std::vector<std::string> others;
        std::size_t int32Count = 0;
        const GU_PrimVDB* vdb = findLabelVdb(*input, group, others, int32Count);
        if (!vdb) {
            std::ostringstream message;
            message << "VDB Interfaces needs an int32 VDB of labels";
            if (others.empty()) {
                message << "; the input" << (group ? " group" : "") << " has no VDB";
            } else {
                message << "; found only";
                for (std::size_t i = 0; i < others.size(); ++i) {
                    message << (i ? ", " : " ") << others[i];
                }
                message << ". Hint: convert the labels to an int32 VDB.";
            }
            addError(SOP_MESSAGE, message.str().c_str());
            return error();
        }
        if (int32Count > 1) {
            addWarning(SOP_MESSAGE, ("using the first of " + std::to_string(int32Count)
                + " int32 VDBs; set Group to choose another").c_str());
        }
        const openvdb::Int32Grid::ConstPtr grid =
            openvdb::gridConstPtrCast<openvdb::Int32Grid>(vdb->getConstGridPtr());
        if (!grid) {
            addError(SOP_MESSAGE, "the int32 VDB is not an openvdb::Int32Grid");
            return error();
        }

        // The pipeline and the arrays come from lib/.
        CookInterrupter interrupter("Extracting VDB interfaces");
        options.repair.interrupter = &interrupter;
        const vdbi::Result result = vdbi::extractInterfaces(*grid, options);
        const std::string warning = vdbi::runWarning(result.statistics);
        if (!warning.empty()) addWarning(SOP_MESSAGE, warning.c_str());
        const vdbi::GeometryArrays arrays = vdbi::makeGeometryArrays(result.mesh);

        writeGeometry(*gdp, arrays);
    } catch (const vdbi::Interrupted& e) {
        gdp->clearAndDestroy();
        addWarning(SOP_MESSAGE, e.what());
    } catch (const std::exception& e) {
        gdp->clearAndDestroy();
        addError(SOP_MESSAGE, e.what());
    }
    return error();
}

} // namespace vdbi_houdini


void
newSopOperator(OP_OperatorTable* table)
{
    if (table == nullptr) return;

    hutil::ParmList parms;

    parms.add(hutil::ParmFactory(PRM_STRING, "group", "Group")
        .setChoiceList(&hutil::PrimGroupMenuInput1)
        .setTooltip("The VDB of labels: the first int32 VDB of this group (of all VDBs if empty).")
        .setDocumentation(
            "Which VDB holds the labels. The first int32 VDB among the primitives of this group"
            " is used; other VDB types are ignored."));

    parms.add(hutil::ParmFactory(PRM_TOGGLE, "remesh", "Remesh")
        .setDefault(PRMoneDefaults)
        .setTooltip("Remesh the patches towards Edge Length.")
        .setDocumentation(
            "Remesh the interface patches towards a target edge length, keeping the curves"
            " where patches meet (on by default, as in the command-line tool). Off gives the"
            " raw extraction: the voxel faces, exact and much faster to cook."));

    parms.add(hutil::ParmFactory(PRM_FLT_J, "edgelength", "Edge Length")
        .setDefault(0.0)
        .setRange(PRM_RANGE_RESTRICTED, 0.0, PRM_RANGE_UI, 10.0)
        .setTooltip("Target edge length in world units; 0 means one voxel.")
        .setDocumentation("Target edge length of remeshing, in world units. 0 means one voxel."));

    parms.add(hutil::ParmFactory(PRM_INT_J, "iterations", "Iterations")
        .setDefault(5)
        .setRange(PRM_RANGE_RESTRICTED, 0, PRM_RANGE_UI, 50)
        .setTooltip("Remeshing iterations.")
        .setDocumentation("Number of remeshing iterations."));

    parms.add(hutil::ParmFactory(PRM_STRING, "constraints", "Separation Constraints")
        .setTooltip("\"A B C; D E F\": labels A and B are always separated by label C.")
        .setDocumentation(
            "Separation constraints, written `A B C; D E F`: in each constraint, labels A and B"
            " never touch but are always separated by label C. Constraints are separated by"
            " semicolons; a separator may not be one of the A or B labels of any constraint."));

    parms.add(hutil::ParmFactory(PRM_STRING, "priority", "Label Priority")
        .setTooltip("Labels in priority order, e.g. \"3 1 2\"; the others follow, smallest first.")
        .setDocumentation(
            "Which label wins where the labels meet in a non-manifold way: the listed labels"
            " first, in the order given (spaces or commas), then all others, smallest first."));

    hvdb::OpenVDBOpFactory("VDB Interfaces", vdbi_houdini::SOP_VDBInterfaces::factory,
        parms, *table)
        .setInternalName("vdbinterfaces")
        .addInput("Int32 VDB of labels")
        .setDocumentation(
            "#icon: COMMON/openvdb\n"
            "#tags: vdb\n"
            "\n"
            "\"\"\"Consistent, manifold interface surfaces between the labels of an int32 VDB."
            "\"\"\"\n"
            "\n"
            "@overview\n"
            "\n"
            "Every pair of touching labels A < B gets one patch of triangles, oriented from A"
            " into B. The patches of each label form a closed surface, and neighbouring"
            " patches share their boundary points (Bischoff and Kobbelt 2006).\n"
            "\n"
            "Primitive attributes: `label_a` and `label_b` (int), `patch` (the patch number)"
            " and `name` (`patch_A_B`, a negative label written `m3` for -3).\n");
}
