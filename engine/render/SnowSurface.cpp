// The renderer's snow surface (Renderer.h, RenderMode::Surface): the mesh the reconstruction left on the GPU
// (engine/surface), drawn with an indexed draw whose vertex shaders read the vertices in place; its shadow on the
// ground, as the colliders cast theirs; and the shadows on it of itself, the colliders and the rigid bodies, through
// a shadow map of the key light.
#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "render/Renderer.h"
#include "surface/SurfaceLayout.h"

namespace firn::render {

namespace {

constexpr GLuint kShadowMapTextureUnit = 1;
// The shadow map's texels: fine enough for a reconstruction cell of a snowball across a picture, cheap to clear.
constexpr int kShadowMapTexels = 2048;
// A point is in the shadow of a surface at least this many reconstruction cells nearer the light: marching cubes'
// facets and the map's texels stay below it, so lit snow does not shadow itself.
constexpr double kShadowBiasCells = 1.0;
// The filter's radius: about a reconstruction cell, so that shadow edges are as soft as the surface is smooth.
constexpr double kShadowFilterCells = 1.0;

}  // namespace

const gl::Buffer* Renderer::particleColors(const ParticleView& particleView, ColorMode mode) {
  const bool oneColor = std::all_of(materialColors_.begin(), materialColors_.end(),
                                    [&](const glm::vec4& color) { return color == materialColors_.front(); });
  if (mode == ColorMode::Material && oneColor) return nullptr;
  const std::size_t particles = particleView.count;
  const std::size_t bytes = std::max<std::size_t>(particles, 1) * sizeof(glm::vec4);
  if (particleColors_.bytes() < bytes) particleColors_ = gl::Buffer(bytes);
  gl::BufferBindings buffers;
  particleView.publish(buffers);
  buffers.storage(FIRN_BINDING_SURFACE_PARTICLE_COLORS, particleColors_);
  particleColorPass_.program().use();
  setAppearance(particleColorPass_.program(), mode);
  particleColorPass_.program().set("coloredParticles", static_cast<unsigned>(particles));
  if (particles > 0) particleColorPass_.runOver(particles, maxWorkGroupsX_, buffers, particleColorTimer_);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  return &particleColors_;
}

void Renderer::drawSnowTriangles(const surface::SurfaceReconstruction& snowSurface) {
  snowArray_.setIndexBuffer(snowSurface.indexBuffer());
  snowSurface.vertexBuffer().bindStorage(FIRN_BINDING_SURFACE_VERTICES);
  snowArray_.bind();
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(3 * snowSurface.stats().triangles), GL_UNSIGNED_INT, nullptr);
}

void Renderer::setShadowBox(const gl::Program& program, const surface::SurfaceReconstruction& snowSurface) const {
  program.set("shadowBoxMinM", glm::vec3(snowSurface.boundsMinM()));
  program.set("shadowBoxMaxM", glm::vec3(snowSurface.boundsMaxM()));
}

// Into the ground-shadow texture, which castGroundShadow has just cleared and filled with the colliders' shadows.
void Renderer::castSnowGroundShadow(const surface::SurfaceReconstruction& snowSurface, const PlaneQuad& ground) {
  if (snowSurface.stats().triangles == 0) return;
  groundShadow_.bind();
  glViewport(0, 0, groundShadow_.size().x, groundShadow_.size().y);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  snowGroundShadowProgram_.use();
  setGround(snowGroundShadowProgram_, ground);
  drawSnowTriangles(snowSurface);
  glDisable(GL_BLEND);
}

void Renderer::renderSnowShadowMap(const surface::SurfaceReconstruction& snowSurface, double timeS,
                                   const std::vector<ObjectPose>& bodyPoses) {
  if (!snowShadowMap_) snowShadowMap_ = gl::Framebuffer(glm::ivec2(kShadowMapTexels), GL_R32F, true);
  snowShadowMap_.bind();
  glViewport(0, 0, kShadowMapTexels, kShadowMapTexels);
  const GLfloat farthest[4] = {1, 1, 1, 1};
  glClearBufferfv(GL_COLOR, 0, farthest);
  glClearBufferfv(GL_DEPTH, 0, farthest);
  if (snowSurface.stats().triangles == 0) return;
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);
  snowShadowMapProgram_.use();
  setShadowBox(snowShadowMapProgram_, snowSurface);
  drawSnowTriangles(snowSurface);

  // The colliders' and bodies' meshes shade the snow too. The map's box is the snow's: depth clamping keeps an object
  // nearer the light than the box, at the box's near side, rather than clipping it away.
  glEnable(GL_DEPTH_CLAMP);
  objectShadowMapProgram_.use();
  setShadowBox(objectShadowMapProgram_, snowSurface);
  surfaceArray_.bind();
  for (const SurfaceDraw& surface : surfaces_) {
    if (surface.isPlane || !isPosed(surface, bodyPoses)) continue;
    objectShadowMapProgram_.set("poseMatrix", surfacePose(surface, timeS, bodyPoses));
    glDrawArrays(GL_TRIANGLES, surface.firstVertex, surface.vertexCount);
  }
  glDisable(GL_DEPTH_CLAMP);
}

void Renderer::drawSnowSurface(const FrameView& view, const surface::SurfaceReconstruction& snowSurface) {
  if (snowSurface.stats().triangles == 0) return;
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  // The surface is closed: only its front faces can be seen.
  glEnable(GL_CULL_FACE);
  glCullFace(GL_BACK);
  snowSurfaceProgram_.use();
  setView(snowSurfaceProgram_, view);
  // A surface rebuilt without colours has one: the (only) material's.
  const glm::vec3 albedoSrgb = snowSurface.stats().withColors || materialColors_.empty()
                                   ? glm::vec3(1.0f) : glm::vec3(materialColors_.front());
  snowSurfaceProgram_.set("albedoScaleSrgb", albedoSrgb);
  setShadowBox(snowSurfaceProgram_, snowSurface);
  const double cellM = snowSurface.nodeSpacingM();
  // The map spans at most the box's diagonal across the light.
  const double texelM = glm::length(snowSurface.boundsMaxM() - snowSurface.boundsMinM()) / kShadowMapTexels;
  snowSurfaceProgram_.set("shadowBiasM", float(kShadowBiasCells * cellM));
  snowSurfaceProgram_.set("shadowFilterTexels", float(std::max(1.5, kShadowFilterCells * cellM / texelM)));
  snowSurfaceProgram_.set("shadowMapDepth", static_cast<int>(kShadowMapTextureUnit));
  snowShadowMap_.color().bind(kShadowMapTextureUnit);
  drawSnowTriangles(snowSurface);
  glDisable(GL_CULL_FACE);
}

}  // namespace firn::render
