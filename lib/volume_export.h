#pragma once
// The scene's field at the nodes of a regular grid, written for other renderers: NRRD
// (attached or detached header), VTK XML image data (.vti, ascii or raw appended), MetaImage
// (.mha) and NIfTI-1 (.nii), in float32 or float64, with the grid's origin and spacing in world
// units.
//
// Node convention (what VTK image data and NRRD with "space origin"/"space directions" mean):
// node (i, j, k) sits at origin + (i hx, j hy, k hz), values are stored with i fastest, then j,
// then k, and a renderer interpolates between nodes.  See docs/export.md.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "lib/geometry.h"
#include "lib/scene.h"

namespace vrv {

struct ExportedNodes {
  Vec3 origin = Vec3::Zero();   // world position of node (0, 0, 0)
  Vec3 spacing = Vec3::Ones();  // node spacing per axis (world units)
  std::array<int, 3> n{0, 0, 0};  // nodes per axis
  std::vector<double> values;     // values[(k * n[1] + j) * n[0] + i]

  double at(int i, int j, int k) const {
    return values[(static_cast<std::size_t>(k) * n[1] + j) * n[0] + i];
  }
  Vec3 position(int i, int j, int k) const {
    return origin + Vec3(i, j, k).cwiseProduct(spacing);
  }
};

// The field on the scene's grid:
//  - no resolution, grid field: the grid's own nodes and values, bit for bit (node layout:
//    nodes on the box faces; cell layout: texel centres, origin half a spacing inside);
//  - no resolution, analytic field: scene.dims nodes per axis on the box faces;
//  - a resolution (each >= 2, at most 2048, else std::invalid_argument naming --resolution):
//    that many nodes on the box faces, each the scene's field at the node (a grid field
//    through its own interpolation).
// Node positions are box.min + i * extent / (n - 1), the same expression GridField uses.
ExportedNodes sample_volume(const Scene& scene, std::optional<std::array<int, 3>> resolution);

enum class SampleType { float32, float64 };
enum class VtiEncoding { ascii, raw_appended };

// "float" / "double" (NRRD), "Float32" / "Float64" (VTK).
std::string nrrd_type_name(SampleType t);
std::string vtk_type_name(SampleType t);

// The values as little-endian raw bytes of the type (float32 rounds to nearest).
std::string raw_bytes(const ExportedNodes& v, SampleType t);

// A NRRD0004 header ending with the blank line.  data_file empty: an attached header (the raw
// bytes follow directly, as nrrd_file writes); else "data file: <data_file>" (detached .nhdr).
// Origin and directions are written with 17 significant digits (exact for double).
std::string nrrd_header(const ExportedNodes& v, SampleType t, const std::string& data_file = "");
// An attached .nrrd: header + raw bytes.
std::string nrrd_file(const ExportedNodes& v, SampleType t);

// A VTKFile of type ImageData, one point-data array named "field"; ascii values are printed
// to round trip (shortest representation of the stored type).  raw_appended stores a UInt64
// byte count followed by the raw bytes (header_type="UInt64").
std::string vti_file(const ExportedNodes& v, SampleType t, VtiEncoding encoding);

// MetaImage (.mha): the text header (Offset, ElementSpacing, identity TransformMatrix, 17
// digits: exact) and the raw little-endian samples after it.
std::string metaimage_file(const ExportedNodes& v, SampleType t);

// NIfTI-1 (.nii): niftilib's header struct, qform and sform both stating the placement (scanner
// coordinates, units unknown: the scene's), the samples at offset 352.  NIfTI-1 stores spacing and
// origin as float32, so its placement is the doubles rounded to float (relative 6e-8).
std::string nifti_file(const ExportedNodes& v, SampleType t);

}  // namespace vrv
