// Scenes built into `tessera render`, named `builtin:NAME` on its command line: a demo that needs
// no file, and the scenes its tests render.
#ifndef TESSERA_TOOLS_TESSERA_SCENE_BUILTIN_SCENE_H_
#define TESSERA_TOOLS_TESSERA_SCENE_BUILTIN_SCENE_H_

#include <memory>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "tools/tessera/scene/scene.h"

namespace tessera::render {

// The prefix that names a built-in scene instead of a file.
inline constexpr char kBuiltinPrefix[] = "builtin:";

// The names OpenBuiltinScene takes (after the prefix).
std::vector<std::string> BuiltinSceneNames();

// The built-in scene `name` ("cornell"), or NOT_FOUND naming it and the scenes there are.
//
// "cornell": a Cornell box two units wide, the floor at y = 0, open towards +Z where the camera
// stands: a checkered white floor (a base colour texture), white ceiling and back wall, red left
// and green right walls, an emissive quad under the ceiling (0.8 x 0.64, larger and dimmer than
// the classic box's, so that caustics of the glass converge sooner), one point light, a tall
// copper box (metallic, roughness 0.35) and a short white box carrying a glass ball
// (transmission 1, IOR 1.5).
// The short box and its ball turn and slide over time_begin() = 0 .. time_end() = 2 s, so frames
// of an animation differ. Cameras: "main" (perspective, 39.3 degrees vertical) and "ortho"
// (orthographic, the same view axis).
absl::StatusOr<std::unique_ptr<SceneFile>> OpenBuiltinScene(const std::string& name);

}  // namespace tessera::render

#endif  // TESSERA_TOOLS_TESSERA_SCENE_BUILTIN_SCENE_H_
