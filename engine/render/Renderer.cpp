#include "render/Renderer.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/matrix.hpp>

#include "gl/Debug.h"
#include "gl/ShaderLibrary.h"
#include "gpu/GpuLayout.h"
#include "gpu/Materials.h"
#include "scene/ColliderMotion.h"

namespace firn::render {

namespace {

// Material colours (sRGB), by material index, repeating: snow near-white with a touch of blue first.
const glm::vec3 kMaterialPaletteSrgb[] = {{0.93f, 0.96f, 1.00f}, {1.00f, 0.88f, 0.74f}, {0.76f, 0.93f, 0.82f},
                                          {0.97f, 0.79f, 0.86f}, {0.78f, 0.85f, 1.00f}, {0.98f, 0.95f, 0.72f}};
const glm::vec3 kGroundAlbedoSrgb{0.60f, 0.56f, 0.50f};
const glm::vec3 kPlaneAlbedoSrgb{0.56f, 0.55f, 0.53f};
const glm::vec3 kColliderAlbedoSrgb{0.60f, 0.45f, 0.36f};     // terracotta
const glm::vec3 kRigidBodyAlbedoSrgb{0.85f, 0.66f, 0.22f};    // ochre: a body the snow moves, told from the colliders
const glm::vec4 kDomainEdgeColor{0.86f, 0.90f, 1.00f, 0.35f};  // sRGB, alpha

// Ground-shadow texels: about half the finest particle spacing, so a contact shadow keeps the particles'
// grain, within bounds that keep the texture cheap to clear and to splat into.
constexpr int kMinShadowTexels = 256;
constexpr int kMaxShadowTexels = 2048;
// The speed scale when nothing in the scene moves or falls.
constexpr float kFallbackSpeedScaleMPerS = 5;
constexpr GLuint kGroundShadowTextureUnit = 0;

int shadowTextureSize(const Scene& scene, float groundHalfSizeM) {
  double finestSpacingM = scene.grid.cellSizeM;
  for (const Body& body : scene.bodies) {
    finestSpacingM = std::min(finestSpacingM, scene.grid.cellSizeM / std::cbrt(body.particlesPerCell));
  }
  const double texels = 2.0 * groundHalfSizeM / (0.5 * finestSpacingM);
  int size = kMinShadowTexels;
  while (size < texels && size < kMaxShadowTexels) size *= 2;
  return size;
}

float speedScale(const Scene& scene) {
  double speedMPerS = 0;
  for (const Body& body : scene.bodies) speedMPerS = std::max(speedMPerS, glm::length(body.velocityMPerS));
  for (const Collider& collider : scene.colliders) {
    speedMPerS = std::max(speedMPerS, fastestColliderSpeedMPerS(scene, collider));
  }
  // Free fall through the domain: v = √(2 g H).
  const double heightM = scene.domainMaxM().y - scene.domainMinM().y;
  speedMPerS = std::max(speedMPerS, std::sqrt(2 * glm::length(scene.gravityMPerS2) * heightM));
  return speedMPerS > 0 ? static_cast<float>(speedMPerS) : kFallbackSpeedScaleMPerS;
}

}  // namespace

const char* renderModeName(RenderMode mode) { return mode == RenderMode::Surface ? "surface" : "particles"; }

const char* colorModeName(ColorMode mode) {
  switch (mode) {
    case ColorMode::Material: return "material";
    case ColorMode::Speed: return "speed";
    case ColorMode::PlasticCompression: return "plastic compression";
    case ColorMode::Stress: return "stress";
  }
  return "unknown";
}

Renderer::Renderer(const Scene& scene)
    : colliders_(scene.colliders), ground_(findGround(scene)), speedScaleMPerS_(speedScale(scene)) {
  // One entry per entry of the simulation's material table (particles carry that index): the scene's materials,
  // then the variants of bodies with their own Lamé scales, drawn in their base material's colour.
  for (const std::size_t i : buildMaterialTable(scene).entryMaterial) {
    const Material& material = scene.materials[i];
    // The stress colour scale: Young's modulus, or for water (no E) the stiffness of its pressure, k γ.
    const double stiffnessPa =
        material.model == MaterialModel::Water ? material.bulkModulusPa * material.gamma : material.youngsModulusPa;
    materialColors_.emplace_back(kMaterialPaletteSrgb[i % std::size(kMaterialPaletteSrgb)], 1.0f);
    materialProperties_.emplace_back(1.0 / stiffnessPa, 1.0 / material.densityKgPerM3, 0.0f, 0.0f);
  }
  GLfloat pointSizeRangePx[2] = {1, 1};
  glGetFloatv(GL_POINT_SIZE_RANGE, pointSizeRangePx);
  maxPointSizePx_ = pointSizeRangePx[1];
  buildPrograms();
  buildGeometry(scene);
  const int shadowTexels = shadowTextureSize(scene, ground_.quad.halfSizeM);
  groundShadow_ = gl::Framebuffer(glm::ivec2(shadowTexels), GL_R16F, false);
  glGetIntegeri_v(GL_MAX_COMPUTE_WORK_GROUP_COUNT, 0, &maxWorkGroupsX_);
}

void Renderer::buildPrograms() {
  gl::ShaderOptions options;
  // GLSL has no empty arrays: a scene without materials (and so without particles) still declares one.
  options.defines.emplace_back("FIRN_MATERIAL_COUNT", std::to_string(std::max<std::size_t>(materialColors_.size(), 1)));
  options.defines.emplace_back("FIRN_COLOR_MODE_MATERIAL", std::to_string(int(ColorMode::Material)));
  options.defines.emplace_back("FIRN_COLOR_MODE_SPEED", std::to_string(int(ColorMode::Speed)));
  options.defines.emplace_back("FIRN_COLOR_MODE_PLASTIC_COMPRESSION", std::to_string(int(ColorMode::PlasticCompression)));
  options.defines.emplace_back("FIRN_COLOR_MODE_STRESS", std::to_string(int(ColorMode::Stress)));
  const gl::ShaderLibrary library(gl::embeddedShaderFiles());
  skyProgram_ = gl::Program::graphics(library, "render/sky.vert", "render/sky.frag", options);
  surfaceProgram_ = gl::Program::graphics(library, "render/surface.vert", "render/surface.frag", options);
  particleProgram_ = gl::Program::graphics(library, "render/particles.vert", "render/particles.frag", options);
  particleShadowProgram_ =
      gl::Program::graphics(library, "render/particle_shadow.vert", "render/particle_shadow.frag", options);
  colliderShadowProgram_ =
      gl::Program::graphics(library, "render/collider_shadow.vert", "render/collider_shadow.frag", options);
  lineProgram_ = gl::Program::graphics(library, "render/lines.vert", "render/lines.frag", options);
  snowSurfaceProgram_ = gl::Program::graphics(library, "render/snow_surface.vert", "render/snow_surface.frag", options);
  snowShadowMapProgram_ =
      gl::Program::graphics(library, "render/snow_shadow_map.vert", "render/snow_shadow_map.frag", options);
  objectShadowMapProgram_ =
      gl::Program::graphics(library, "render/object_shadow_map.vert", "render/snow_shadow_map.frag", options);
  snowGroundShadowProgram_ =
      gl::Program::graphics(library, "render/snow_ground_shadow.vert", "render/collider_shadow.frag", options);
  particleColorPass_ = gl::ComputePass(library, "render/particle_colors.comp", options);
}

void Renderer::buildGeometry(const Scene& scene) {
  std::vector<SurfaceVertex> vertices;
  auto add = [&](const std::vector<SurfaceVertex>& mesh, SurfaceDraw draw) {
    draw.firstVertex = static_cast<GLint>(vertices.size());
    draw.vertexCount = static_cast<GLsizei>(mesh.size());
    vertices.insert(vertices.end(), mesh.begin(), mesh.end());
    surfaces_.push_back(draw);
  };
  const float checkerM = checkerCellM(scene);
  const float fadeM = ground_.quad.halfSizeM;
  if (ground_.colliderIndex < 0) {
    add(quadTriangles(ground_.quad), {0, 0, kGroundAlbedoSrgb, -1, -1, checkerM, fadeM, true, true});
  }
  for (const SceneObject& object : sceneObjects(scene)) {
    if (object.kind == ObjectKind::RigidBody) {
      add(objectTriangles(object), {0, 0, kRigidBodyAlbedoSrgb, -1, object.index, 0.0f, 0.0f, false, false});
      continue;
    }
    const Collider& collider = scene.colliders[std::size_t(object.index)];
    if (collider.shape != ColliderShape::Plane) {
      add(objectTriangles(object), {0, 0, kColliderAlbedoSrgb, object.index, -1, 0.0f, 0.0f, false, false});
      continue;
    }
    // A plane keeps its own quad, whose coordinates carry the checkerboard and the fade, moved into the collider's
    // frame (origin at the pivot) like the other objects' meshes.
    const bool isGround = object.index == ground_.colliderIndex;
    if (!isGround && !planeCutsDomain(scene, collider.pointM, collider.normal)) continue;
    PlaneQuad quad = isGround ? ground_.quad : planeQuad(scene, collider.pointM, collider.normal);
    quad.centerM = glm::vec3(glm::dvec3(quad.centerM) - collider.pivotM);
    add(quadTriangles(quad), {0, 0, isGround ? kGroundAlbedoSrgb : kPlaneAlbedoSrgb, object.index, -1, checkerM,
                              quad.halfSizeM, isGround, true});
  }
  surfaceVertices_ = gl::Buffer::fromVector(vertices);
  surfaceArray_.setFloatAttribute(0, surfaceVertices_, 3, sizeof(SurfaceVertex), offsetof(SurfaceVertex, positionM));
  surfaceArray_.setFloatAttribute(1, surfaceVertices_, 3, sizeof(SurfaceVertex), offsetof(SurfaceVertex, normal));
  surfaceArray_.setFloatAttribute(2, surfaceVertices_, 2, sizeof(SurfaceVertex),
                                  offsetof(SurfaceVertex, planeCoordinatesM));

  // The interior's edges: where the walls stop the particles (GridSpec::wallCells inside the domain).
  const std::vector<glm::vec3> edges = boxEdges(glm::vec3(scene.grid.interiorMinM()), glm::vec3(scene.grid.interiorMaxM()));
  edgeVertices_ = gl::Buffer::fromVector(edges);
  edgeArray_.setFloatAttribute(0, edgeVertices_, 3, sizeof(glm::vec3), 0);
  edgeVertexCount_ = static_cast<GLsizei>(edges.size());
}

PlaneQuad Renderer::groundAt(double timeS) const {
  PlaneQuad quad = ground_.quad;
  quad.centerM += ground_.velocityMPerS * static_cast<float>(timeS);
  return quad;
}

bool Renderer::isPosed(const SurfaceDraw& surface, const std::vector<ObjectPose>& bodyPoses) {
  return surface.bodyIndex < 0 || std::size_t(surface.bodyIndex) < bodyPoses.size();
}

glm::mat4 Renderer::surfacePose(const SurfaceDraw& surface, double timeS,
                                const std::vector<ObjectPose>& bodyPoses) const {
  ObjectPose pose;
  if (surface.bodyIndex >= 0) {
    pose = bodyPoses[std::size_t(surface.bodyIndex)];
  } else if (surface.colliderIndex >= 0) {
    pose = colliderObjectPose(colliders_[std::size_t(surface.colliderIndex)], timeS);
  } else {
    return glm::mat4(1.0f);  // the ground without a collider, built where it lies
  }
  // x = position + orientation · p (SceneObjects.h; for a collider docs/algorithm.md eq. 31 with p = x_rest − pivot),
  // in double before the one rounding to float.
  glm::dmat4 matrix = glm::dmat4(glm::mat3_cast(pose.orientation));
  matrix[3] = glm::dvec4(pose.positionM, 1.0);
  return glm::mat4(matrix);
}

void Renderer::setView(const gl::Program& program, const FrameView& view) const {
  program.set("viewMatrix", view.view);
  program.set("projectionMatrix", view.projection);
  program.set("inverseProjectionMatrix", glm::inverse(view.projection));
  program.set("viewportSizePx", view.viewportPx);
  program.set("viewportOriginPx", glm::vec2(viewportOriginPx_));
}

void Renderer::setGround(const gl::Program& program, const PlaneQuad& ground) const {
  program.set("groundCentreM", ground.centerM);
  program.set("groundNormal", ground.normal);
  program.set("groundTangentU", ground.tangentU);
  program.set("groundTangentV", ground.tangentV);
  program.set("groundHalfSizeM", ground.halfSizeM);
}

void Renderer::draw(const ParticleView& particles, const std::vector<ObjectPose>& bodyPoses, const Camera& camera,
                    glm::ivec2 viewportPx, ColorMode mode, const surface::SurfaceReconstruction* snowSurface) {
  if (viewportPx.x <= 0 || viewportPx.y <= 0) return;  // a minimised window
  const std::size_t particleCount = particles.count;
  const double timeS = particles.timeS;
  particleBuffers_ = gl::BufferBindings();
  particles.publish(particleBuffers_);
  const GLuint target = gl::Framebuffer::boundForDrawing();
  // The particles were last written by compute passes; vertex shaders read them as storage buffers.
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  const PlaneQuad ground = groundAt(timeS);
  castGroundShadow(snowSurface != nullptr ? 0 : particleCount, timeS, bodyPoses, ground);
  if (snowSurface != nullptr) {
    castSnowGroundShadow(*snowSurface, ground);
    renderSnowShadowMap(*snowSurface, timeS, bodyPoses);
  }

  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, target);
  glViewport(viewportOriginPx_.x, viewportOriginPx_.y, viewportPx.x, viewportPx.y);
  glDepthMask(GL_TRUE);
  const GLfloat farDepth = 1;
  glClearBufferfv(GL_DEPTH, 0, &farDepth);
  const float aspect = float(viewportPx.x) / float(viewportPx.y);
  const FrameView view{camera.view(), camera.projection(aspect), glm::vec2(viewportPx), camera.positionM};
  drawSky(view);
  drawSurfaces(view, timeS, bodyPoses, ground);
  if (snowSurface != nullptr) {
    drawSnowSurface(view, *snowSurface);
  } else {
    drawParticles(view, particleCount, mode);
  }
  if (domainEdges_) drawDomainEdges(view);

  glDisable(GL_BLEND);
  glDisable(GL_CULL_FACE);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_PROGRAM_POINT_SIZE);
  glDepthMask(GL_TRUE);
  glBindVertexArray(0);
  glUseProgram(0);
  gl::checkPass("render");
}

// The ground-shadow texture: optical depth of the key light's shadow, summed over particles, colliders and bodies.
void Renderer::castGroundShadow(std::size_t particleCount, double timeS, const std::vector<ObjectPose>& bodyPoses,
                                const PlaneQuad& ground) {
  groundShadow_.bind();
  const glm::ivec2 texels = groundShadow_.size();
  glViewport(0, 0, texels.x, texels.y);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  const GLfloat noShadow[4] = {0, 0, 0, 0};
  glClearBufferfv(GL_COLOR, 0, noShadow);
  glEnable(GL_BLEND);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ONE);
  if (particleCount > 0) {
    particleShadowProgram_.use();
    particleBuffers_.bindFor(particleShadowProgram_);
    setGround(particleShadowProgram_, ground);
    particleShadowProgram_.set("shadowTexelSizeM", 2 * ground.halfSizeM / float(texels.x));
    particleShadowProgram_.set("maxPointSizePx", maxPointSizePx_);
    particleShadowProgram_.set("materialProperties", materialProperties_);
    glEnable(GL_PROGRAM_POINT_SIZE);
    noAttributes_.bind();
    glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(particleCount));
  }
  colliderShadowProgram_.use();
  setGround(colliderShadowProgram_, ground);
  surfaceArray_.bind();
  for (const SurfaceDraw& surface : surfaces_) {
    if (surface.isPlane || !isPosed(surface, bodyPoses)) continue;
    colliderShadowProgram_.set("poseMatrix", surfacePose(surface, timeS, bodyPoses));
    glDrawArrays(GL_TRIANGLES, surface.firstVertex, surface.vertexCount);
  }
  glDisable(GL_BLEND);
}

void Renderer::drawSky(const FrameView& view) {
  glDisable(GL_DEPTH_TEST);
  skyProgram_.use();
  setView(skyProgram_, view);
  noAttributes_.bind();
  glDrawArrays(GL_TRIANGLES, 0, 3);
}

void Renderer::drawSurfaces(const FrameView& view, double timeS, const std::vector<ObjectPose>& bodyPoses,
                            const PlaneQuad& ground) {
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glCullFace(GL_BACK);
  surfaceProgram_.use();
  setView(surfaceProgram_, view);
  setGround(surfaceProgram_, ground);
  surfaceProgram_.set("cameraPositionM", view.cameraPositionM);
  surfaceProgram_.set("groundShadowOpticalDepth", static_cast<int>(kGroundShadowTextureUnit));
  groundShadow_.color().bind(kGroundShadowTextureUnit);
  surfaceArray_.bind();
  for (const SurfaceDraw& surface : surfaces_) {
    if (!isPosed(surface, bodyPoses)) continue;
    // Planes are seen from their free side only: from behind one, the camera looks through it. A mesh is drawn from
    // both sides, since a file's triangles may wind either way, and lit on the side seen (surface.frag).
    if (surface.isPlane) {
      glEnable(GL_CULL_FACE);
    } else {
      glDisable(GL_CULL_FACE);
    }
    surfaceProgram_.set("poseMatrix", surfacePose(surface, timeS, bodyPoses));
    surfaceProgram_.set("albedoSrgb", surface.albedoSrgb);
    surfaceProgram_.set("checkerCellM", surface.checkerCellM);
    surfaceProgram_.set("fadeHalfSizeM", surface.fadeHalfSizeM);
    surfaceProgram_.set("receivesShadow", surface.isGround ? 1 : 0);
    glDrawArrays(GL_TRIANGLES, surface.firstVertex, surface.vertexCount);
  }
  glDisable(GL_CULL_FACE);
}

void Renderer::drawParticles(const FrameView& view, std::size_t particleCount, ColorMode mode) {
  if (particleCount == 0) return;
  glEnable(GL_DEPTH_TEST);
  glEnable(GL_PROGRAM_POINT_SIZE);
  particleProgram_.use();
  particleBuffers_.bindFor(particleProgram_);
  setView(particleProgram_, view);
  particleProgram_.set("maxPointSizePx", maxPointSizePx_);
  setAppearance(particleProgram_, mode);
  noAttributes_.bind();
  glDrawArrays(GL_POINTS, 0, static_cast<GLsizei>(particleCount));
}

// The uniforms of render/particle_appearance.glsl.
void Renderer::setAppearance(const gl::Program& program, ColorMode mode) const {
  program.set("colorMode", static_cast<int>(mode));
  program.set("materialColorSrgb", materialColors_);
  program.set("materialProperties", materialProperties_);
  program.set("speedScaleMPerS", speedScaleMPerS_);
}

void Renderer::drawDomainEdges(const FrameView& view) {
  glEnable(GL_DEPTH_TEST);
  glDepthMask(GL_FALSE);  // translucent: nothing drawn later should be hidden by them
  glEnable(GL_BLEND);
  // Over the colour; the picture stays opaque.
  glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
  lineProgram_.use();
  setView(lineProgram_, view);
  lineProgram_.set("lineColor", kDomainEdgeColor);
  edgeArray_.bind();
  glDrawArrays(GL_LINES, 0, edgeVertexCount_);
}

OffscreenRenderer::OffscreenRenderer(const Scene& scene, glm::ivec2 sizePx) : renderer_(scene), target_(sizePx) {}

Image OffscreenRenderer::render(const ParticleView& particles, const std::vector<ObjectPose>& bodyPoses,
                                const Camera& camera, ColorMode mode,
                                const surface::SurfaceReconstruction* snowSurface) {
  const GLuint previousTarget = gl::Framebuffer::boundForDrawing();
  GLint previousViewport[4] = {0, 0, 0, 0};
  glGetIntegerv(GL_VIEWPORT, previousViewport);
  target_.bind();
  renderer_.draw(particles, bodyPoses, camera, size(), mode, snowSurface);
  Image image{size().x, size().y, target_.readColorRgba8()};
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, previousTarget);
  glViewport(previousViewport[0], previousViewport[1], previousViewport[2], previousViewport[3]);
  return image;
}

}  // namespace firn::render
