# Writes the default scene file into a C++ source as a raw string literal, so that
# `suturesim` with no argument runs exactly parameters/stitch_interrupted.prm.
file(READ ${INPUT} CONTENT)
get_filename_component(NAME ${INPUT} NAME)
file(WRITE ${OUTPUT}.tmp
"// Generated from parameters/${NAME} by cmake/embed_scene.cmake. Do not edit.
#include <suturesim/scene/default_scene.h>
namespace suturesim::scene
{
  const char *default_scene_name = \"${NAME}\";
  const char *default_scene_text = R\"suturesim_prm(${CONTENT})suturesim_prm\";
}
")
file(COPY_FILE ${OUTPUT}.tmp ${OUTPUT} ONLY_IF_DIFFERENT)
file(REMOVE ${OUTPUT}.tmp)
