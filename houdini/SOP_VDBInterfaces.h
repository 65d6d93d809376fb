// SPDX-License-Identifier: Apache-2.0
/// @file houdini/SOP_VDBInterfaces.h
/// @brief The "VDB Interfaces" SOP: an int32 label VDB in, the interface patches between its
/// labels out as triangles with primitive attributes label_a, label_b, patch and name.
/// @details A thin layer of HDK calls over lib/ (vdbi::extractInterfaces, GeometryArrays).
/// Include this header only from SOP_VDBInterfaces.cc: SOP_NodeVDB.h includes UT_DSOVersion.h,
/// which must appear in exactly one translation unit of the DSO.

#ifndef VDBI_HOUDINI_SOP_VDB_INTERFACES_HAS_BEEN_INCLUDED
#define VDBI_HOUDINI_SOP_VDB_INTERFACES_HAS_BEEN_INCLUDED

#include <openvdb_houdini/SOP_NodeVDB.h>

class OP_Context;
class OP_Network;
class OP_Node;
class OP_Operator;

namespace vdbi_houdini {

class SOP_VDBInterfaces : public openvdb_houdini::SOP_NodeVDB
{
public:
    SOP_VDBInterfaces(OP_Network* net, const char* name, OP_Operator* op);
    ~SOP_VDBInterfaces() override = default;

    static OP_Node* factory(OP_Network* net, const char* name, OP_Operator* op);

protected:
    /// Called by SOP_NodeVDB::cookMySop (which is final): the whole cook, errors reported
    /// with addError/addWarning, never thrown.
    OP_ERROR cookVDBSop(OP_Context& context) override;
    /// Greys out the remeshing parameters while remeshing is off.
    bool updateParmsFlags() override;
};

} // namespace vdbi_houdini

#endif // VDBI_HOUDINI_SOP_VDB_INTERFACES_HAS_BEEN_INCLUDED
