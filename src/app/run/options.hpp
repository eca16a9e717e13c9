#pragma once
/// @file The preset's keys mapped to the typed options of every stage, in one place (each
/// fracture method maps its own [simulation] keys in its folder: fracture/method.hpp). A test
/// checks that every option struct's defaults are the schema's.

#include "fracture/run.hpp"
#include "io/preset.hpp"
#include "mesh/surface.hpp"
#include "post/pieces.hpp"
#include "render/bake.hpp"
#include "sim/fem_model.hpp"
#include "sim/growth_field.hpp"
#include "sim/property_field.hpp"

#include <string>

namespace crackle::app {

mesh::SurfaceOptions surface_options(const io::Preset& preset);
sim::GrowthOptions growth_options(const io::Preset& preset);
/// Reads [variation.<property>]; loads the image of an image pattern (InputError if it cannot).
sim::VariationOptions variation_options(const io::Preset& preset, const std::string& property);

/// [simulation] keys of the equilibrium solver.
sim::FemOptions fem_options(const io::Preset& preset);
/// [simulation] keys of the fracture loop that every method reads.
fracture::FractureOptions fracture_options(const io::Preset& preset);

post::PostOptions post_options(const io::Preset& preset);
/// The [bake] section, the maps' pixels on the preset's own surface (io::map_size; a bake of
/// pieces from another tile sizes them by io::MapSizeRequest::on).
render::BakeOptions bake_options(const io::Preset& preset);
/// The same, its maps' pixels on the pieces' tile (a pattern loaded from a file keeps its own).
render::BakeOptions bake_options(const io::Preset& preset, const post::PieceMesh& pieces);

} // namespace crackle::app
