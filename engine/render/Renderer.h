#pragma once
// The renderer (engine/render, docs/architecture.md): particles drawn in place from the simulation's buffers as
// lit sphere impostors, or the snow's reconstructed surface drawn from the GPU's mesh (SnowSurface.cpp); the
// colliders and rigid bodies as lit meshes (scene/SceneObjects.h), the ground with the snow's and their shadows, the
// domain's edges on request; and offscreen capture into an Image.
#include <cstddef>
#include <iterator>
#include <vector>

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "gl/Buffer.h"
#include "gl/BufferBindings.h"
#include "gl/ComputePass.h"
#include "gl/Framebuffer.h"
#include "gl/Program.h"
#include "gpu/ParticleView.h"
#include "render/Camera.h"
#include "render/Geometry.h"
#include "render/Image.h"
#include "scene/Scene.h"
#include "scene/SceneObjects.h"
#include "surface/SurfaceReconstruction.h"

namespace firn::render {

enum class ColorMode {
  Material,            // a palette colour per material; snow near-white with a touch of blue
  Speed,               // |v| through viridis, up to the scene's speed scale
  PlasticCompression,  // J_P on a log scale: blue compacted, neutral at 1, red stretched
  Stress,              // Frobenius norm of the Kirchhoff stress over Young's modulus, log scale, inferno
};
constexpr ColorMode kColorModes[] = {ColorMode::Material, ColorMode::Speed, ColorMode::PlasticCompression,
                                     ColorMode::Stress};
constexpr int kColorModeCount = static_cast<int>(std::size(kColorModes));
// A short name for a user interface: "material", "speed", "plastic compression", "stress".
const char* colorModeName(ColorMode mode);

// How snow is drawn: each particle as a lit sphere, or the surface reconstructed from them (engine/surface,
// docs/surfaces.md), lit as snow and shadowed by itself.
enum class RenderMode { Particles, Surface };
const char* renderModeName(RenderMode mode);  // "particles", "surface"

class Renderer {
 public:
  // Builds the programs (from the embedded shaders, for this scene's materials) and the meshes of its colliders and
  // rigid bodies. Needs a current OpenGL 4.3 context.
  explicit Renderer(const Scene& scene);

  // Draws into the currently bound draw framebuffer, which needs a depth buffer, over the viewport
  // (0, 0)–viewportPx: sky, colliders where they are at the particles' time, rigid body i at bodyPoses[i]
  // (Simulation::rigidBodyPoses()), the ground with its shadow, the particles read in place from their buffers, and
  // the domain's edges if setDomainEdges(true). Bodies past the end of bodyPoses are not drawn (the viewer's spare
  // balls before they are thrown). Colours are written sRGB-encoded (leave GL_FRAMEBUFFER_SRGB off). Leaves
  // blending, culling, depth test and point size off. With `snowSurface` (reconstructed from these particles, with
  // particleColors' colours for `mode`) the snow is drawn as that surface instead of its particles. A view of no
  // particles (ParticleView{}) draws the scene without them at t = 0.
  void draw(const ParticleView& particles, const std::vector<ObjectPose>& bodyPoses, const Camera& camera,
            glm::ivec2 viewportPx, ColorMode mode, const surface::SurfaceReconstruction* snowSurface = nullptr);

  // Where draw()'s viewport starts in the framebuffer (the window's view beside the scene editor's panel).
  void setViewportOrigin(glm::ivec2 originPx) { viewportOriginPx_ = originPx; }

  // Whether draw() outlines the domain's box (off by default: the pictures show the snow, not the box).
  void setDomainEdges(bool shown) { domainEdges_ = shown; }
  bool domainEdges() const { return domainEdges_; }

  // The speed at the top of the speed colour map (m/s): the fastest initial body or collider, or the speed
  // of a fall through the domain's height, whichever is larger.
  float speedScaleMPerS() const { return speedScaleMPerS_; }

  // Each of the simulation's particles' linear albedo in colour mode `mode` (a vec4 per particle, computed on the
  // GPU), for SurfaceReconstruction::reconstruct to carry onto the surface; null when every particle has the same
  // colour (one material's, in material mode), which the renderer then gives the whole surface without a splat.
  const gl::Buffer* particleColors(const ParticleView& particles, ColorMode mode);

 private:
  // A mesh built in its object's frame (SceneObjects.h; the ground without a collider, in the world's), moved there
  // each frame by its collider's pose or its body's.
  struct SurfaceDraw {
    GLint firstVertex;
    GLsizei vertexCount;
    glm::vec3 albedoSrgb;
    int colliderIndex;    // whose motion moves it; −1: not a collider's
    int bodyIndex;        // whose pose moves it; −1: not a rigid body's
    float checkerCellM;   // planes
    float fadeHalfSizeM;  // planes
    bool isGround;
    bool isPlane;         // seen from its free side only; casts no shadow (it would cover the ground)
  };
  struct FrameView {
    glm::mat4 view;
    glm::mat4 projection;
    glm::vec2 viewportPx;
    glm::vec3 cameraPositionM;
  };

  void buildPrograms();
  void buildGeometry(const Scene& scene);
  PlaneQuad groundAt(double timeS) const;
  void setView(const gl::Program& program, const FrameView& view) const;
  void setGround(const gl::Program& program, const PlaneQuad& ground) const;
  void castGroundShadow(std::size_t particleCount, double timeS, const std::vector<ObjectPose>& bodyPoses,
                        const PlaneQuad& ground);
  void drawSky(const FrameView& view);
  void drawSurfaces(const FrameView& view, double timeS, const std::vector<ObjectPose>& bodyPoses,
                    const PlaneQuad& ground);
  void drawParticles(const FrameView& view, std::size_t particleCount, ColorMode mode);
  void drawDomainEdges(const FrameView& view);
  void setAppearance(const gl::Program& program, ColorMode mode) const;
  // The snow's surface (SnowSurface.cpp): its shadow on the ground, its shadow map, and the surface itself.
  void castSnowGroundShadow(const surface::SurfaceReconstruction& snowSurface, const PlaneQuad& ground);
  void renderSnowShadowMap(const surface::SurfaceReconstruction& snowSurface, double timeS,
                           const std::vector<ObjectPose>& bodyPoses);
  void drawSnowSurface(const FrameView& view, const surface::SurfaceReconstruction& snowSurface);
  void drawSnowTriangles(const surface::SurfaceReconstruction& snowSurface);
  void setShadowBox(const gl::Program& program, const surface::SurfaceReconstruction& snowSurface) const;

  gl::Program skyProgram_;
  gl::Program surfaceProgram_;
  gl::Program particleProgram_;
  gl::Program particleShadowProgram_;
  gl::Program colliderShadowProgram_;
  gl::Program lineProgram_;
  gl::Program snowSurfaceProgram_;
  gl::Program snowShadowMapProgram_;
  gl::Program objectShadowMapProgram_;
  gl::Program snowGroundShadowProgram_;
  gl::ComputePass particleColorPass_;  // render/particle_colors.comp
  gl::PassTimer particleColorTimer_;   // not switched on: ComputePass dispatches through one
  gl::BufferBindings particleBuffers_;  // draw()'s particles, at their binding points

  gl::VertexArray noAttributes_;  // for the draws that read no vertex attributes
  gl::Buffer surfaceVertices_;
  gl::VertexArray surfaceArray_;
  std::vector<SurfaceDraw> surfaces_;
  gl::Buffer edgeVertices_;
  gl::VertexArray edgeArray_;
  GLsizei edgeVertexCount_ = 0;
  bool domainEdges_ = false;
  glm::ivec2 viewportOriginPx_{0, 0};

  // Whether draw() shows the surface: a rigid body's only with a pose.
  static bool isPosed(const SurfaceDraw& surface, const std::vector<ObjectPose>& bodyPoses);
  // The rigid motion that carries a surface's mesh from its object's frame to where the object is at timeS.
  glm::mat4 surfacePose(const SurfaceDraw& surface, double timeS, const std::vector<ObjectPose>& bodyPoses) const;

  std::vector<Collider> colliders_;  // the scene's, whose poses move the surfaces
  Ground ground_;
  gl::Framebuffer groundShadow_;  // optical depth of the key light's shadow over the ground quad
  gl::Framebuffer snowShadowMap_;  // depth towards the key light of the snow's surface (render/shadow_map.glsl)
  gl::VertexArray snowArray_;      // the snow's index buffer, no attributes
  gl::Buffer particleColors_;      // particleColors()'s
  GLint maxWorkGroupsX_ = 65535;
  std::vector<glm::vec4> materialColors_;      // sRGB palette colour, 1
  std::vector<glm::vec4> materialProperties_;  // 1 / Young's modulus (1/Pa), 1 / rest density (m³/kg)
  float speedScaleMPerS_ = 1;
  float maxPointSizePx_ = 1;
};

// Renders pictures into its own framebuffer and reads them back.
class OffscreenRenderer {
 public:
  OffscreenRenderer(const Scene& scene, glm::ivec2 sizePx);
  // One picture of the simulation's current state; leaves the bound framebuffer and viewport as they were.
  // The rigid bodies at bodyPoses; with `snowSurface`, the snow as that surface (Renderer::draw).
  Image render(const ParticleView& particles, const std::vector<ObjectPose>& bodyPoses, const Camera& camera,
               ColorMode mode, const surface::SurfaceReconstruction* snowSurface = nullptr);
  const gl::Buffer* particleColors(const ParticleView& particles, ColorMode mode) {
    return renderer_.particleColors(particles, mode);
  }
  void setDomainEdges(bool shown) { renderer_.setDomainEdges(shown); }
  glm::ivec2 size() const { return target_.size(); }

 private:
  Renderer renderer_;
  gl::Framebuffer target_;
};

}  // namespace firn::render
