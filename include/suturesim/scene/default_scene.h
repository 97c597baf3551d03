#pragma once
/// @file The scene run when `suturesim` is given no scene file: the text of
/// parameters/stitch_interrupted.prm, embedded at build time by cmake/embed_scene.cmake.

namespace suturesim::scene
{
  extern const char *default_scene_name;
  extern const char *default_scene_text;
} // namespace suturesim::scene
