// The point-sprite renderer on llvmpipe. Pictures are checked against the camera's own projection of the
// scene's geometry (coverage, bounds, colours by region), never against stored pixels.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/trigonometric.hpp>

#include "Error.h"
#include "GlTest.h"
#include "gl/Framebuffer.h"
#include "render/Renderer.h"
#include "scene/Scene.h"
#include "scene/SceneObjects.h"
#include "sim/Simulation.h"
#include "surface/SurfaceReconstruction.h"
#include "voxelizer/Mesh.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wunused-function"
#define STB_IMAGE_IMPLEMENTATION
#include <stb_image.h>
#pragma GCC diagnostic pop

namespace {

using firn::Scene;
using firn::Simulation;
using firn::render::Camera;
using firn::render::ColorMode;
using firn::render::Image;
using firn::render::Renderer;

const glm::ivec2 kImageSize(320, 240);

// A 1 m domain of 40³ cells of 2.5 cm; at 8 particles per cell the particle spacing s is 1.25 cm.
constexpr double kSpacingM = 0.0125;

Scene sceneFromJson(const std::string& bodies, const std::string& colliders = "[]") {
  return firn::parseScene(R"({
    "grid": { "origin": [0, 0, 0], "cells": [40, 40, 40], "cell_size": 0.025 },
    "time": { "dt": 1e-3, "frame_rate": 50, "frames": 10 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": )" + bodies + R"(,
    "colliders": )" + colliders + "}",
                          "render test scene");
}

std::string box(const std::string& minM, const std::string& maxM, const std::string& velocity = "[0, 0, 0]") {
  return R"({ "shape": "box", "min": )" + minM + R"(, "max": )" + maxM + R"(, "material": "snow", "velocity": )" +
         velocity + " }";
}

// Looks at the box [0.4, 0.5, 0.4]–[0.6, 0.7, 0.6] from the front, 23° from below, so that only sky lies
// behind it: the ground, and the particles' shadow on it, stay out of the picture.
Camera cameraBelowBox() {
  Camera camera;
  camera.positionM = {0.62f, 0.30f, 1.15f};
  camera.targetM = {0.5f, 0.6f, 0.5f};
  camera.fovDeg = 40;
  camera.nearM = 0.01f;
  camera.farM = 10.0f;
  return camera;
}

struct Pixel {
  int r, g, b, a;
};

Pixel pixelAt(const Image& image, int x, int y) {
  const std::size_t i = (std::size_t(y) * std::size_t(image.width) + std::size_t(x)) * 4;
  return {image.rgba[i], image.rgba[i + 1], image.rgba[i + 2], image.rgba[i + 3]};
}

int largestChannelDifference(const Pixel& a, const Pixel& b) {
  return std::max({std::abs(a.r - b.r), std::abs(a.g - b.g), std::abs(a.b - b.b)});
}

// Draws with `particleCount` particles (from the simulation's buffers when given), or their surface, into a fresh
// framebuffer.
Image renderFrame(Renderer& renderer, const Simulation* simulation, const Camera& camera, ColorMode mode,
                  const firn::surface::SurfaceReconstruction* snowSurface = nullptr) {
  firn::gl::Framebuffer target(kImageSize);
  target.bind();
  if (simulation != nullptr) {
    renderer.draw(simulation->particleView(), simulation->rigidBodyPoses(), camera, kImageSize, mode, snowSurface);
  } else {
    renderer.draw(firn::ParticleView{}, {}, camera, kImageSize, mode);
  }
  Image image{kImageSize.x, kImageSize.y, target.readColorRgba8()};
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
  return image;
}

// Where a world point lands in the picture: pixel coordinates, x to the right, y down from the top row.
glm::dvec2 projectToPixels(const Camera& camera, const glm::dvec3& pointM) {
  const glm::dmat4 viewProjection =
      glm::dmat4(camera.projection(float(kImageSize.x) / float(kImageSize.y))) * glm::dmat4(camera.view());
  const glm::dvec4 clip = viewProjection * glm::dvec4(pointM, 1.0);
  const glm::dvec2 ndc = glm::dvec2(clip) / clip.w;
  return {(ndc.x + 1) / 2 * kImageSize.x, (1 - ndc.y) / 2 * kImageSize.y};
}

// Convex hull (Andrew's monotone chain) of projected points: the silhouette of a convex body.
std::vector<glm::dvec2> convexHull(std::vector<glm::dvec2> points) {
  std::sort(points.begin(), points.end(), [](const glm::dvec2& a, const glm::dvec2& b) {
    return a.x < b.x || (a.x == b.x && a.y < b.y);
  });
  auto turn = [](const glm::dvec2& o, const glm::dvec2& a, const glm::dvec2& b) {
    return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
  };
  std::vector<glm::dvec2> hull(2 * points.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && turn(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (std::size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && turn(hull[k - 2], hull[k - 1], points[i]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
  return hull;
}

struct Silhouette {
  double areaPx = 0;
  double perimeterPx = 0;
  glm::dvec2 minPx{0.0}, maxPx{0.0};
  std::vector<glm::dvec2> hullPx;  // counter-clockwise in (x, y)
};

// Signed distance (px) from a point to a convex polygon's outline: negative inside.
double signedDistanceToHull(const std::vector<glm::dvec2>& hull, const glm::dvec2& point) {
  bool outside = false;
  double nearest = 1e30;
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const glm::dvec2 a = hull[i], b = hull[(i + 1) % hull.size()];
    const glm::dvec2 edge = b - a;
    const double along = glm::clamp(glm::dot(point - a, edge) / glm::dot(edge, edge), 0.0, 1.0);
    nearest = std::min(nearest, glm::length(point - (a + along * edge)));
    // Andrew's chain runs counter-clockwise in (x, y): the inside lies to the left of every edge.
    outside = outside || edge.x * (point.y - a.y) - edge.y * (point.x - a.x) < 0;
  }
  return outside ? nearest : -nearest;
}

Silhouette boxSilhouette(const Camera& camera, const glm::dvec3& minM, const glm::dvec3& maxM) {
  std::vector<glm::dvec2> corners;
  for (int i = 0; i < 8; ++i) {
    corners.push_back(projectToPixels(
        camera, {(i & 1) ? maxM.x : minM.x, (i & 2) ? maxM.y : minM.y, (i & 4) ? maxM.z : minM.z}));
  }
  const std::vector<glm::dvec2> hull = convexHull(corners);
  Silhouette silhouette;
  silhouette.minPx = silhouette.maxPx = hull[0];
  for (std::size_t i = 0; i < hull.size(); ++i) {
    const glm::dvec2& a = hull[i];
    const glm::dvec2& b = hull[(i + 1) % hull.size()];
    silhouette.areaPx += 0.5 * (a.x * b.y - b.x * a.y);
    silhouette.perimeterPx += glm::length(b - a);
    silhouette.minPx = glm::min(silhouette.minPx, a);
    silhouette.maxPx = glm::max(silhouette.maxPx, a);
  }
  silhouette.areaPx = std::abs(silhouette.areaPx);
  silhouette.hullPx = hull;
  return silhouette;
}

// How many pixels a metre across the view covers at the box's corner nearest the camera (where it covers most).
double pixelsPerMetreAtNearestCorner(const Camera& camera, const glm::dvec3& minM, const glm::dvec3& maxM) {
  const double focalPx = 0.5 * kImageSize.y / std::tan(glm::radians(double(camera.fovDeg)) / 2);
  double nearestM = 1e9;
  for (int i = 0; i < 8; ++i) {
    const glm::dvec3 cornerM((i & 1) ? maxM.x : minM.x, (i & 2) ? maxM.y : minM.y, (i & 4) ? maxM.z : minM.z);
    nearestM = std::min(nearestM, glm::length(cornerM - glm::dvec3(camera.positionM)));
  }
  return focalPx / nearestM;
}

// Pixels the particles change: more than 8 of 255 in some channel. Rendering is deterministic (the picture
// without particles comes out the same twice, bit for bit), so nothing else changes a pixel; colour alone
// cannot tell snow from this sky, as snow in shade turns the sky's blue-grey, to within 30 levels.
constexpr int kSnowThreshold = 8;

struct Coverage {
  int pixels = 0;
  glm::ivec2 minPx{kImageSize}, maxPx{-1};
};

Coverage snowCoverage(const Image& withParticles, const Image& background) {
  Coverage coverage;
  for (int y = 0; y < kImageSize.y; ++y) {
    for (int x = 0; x < kImageSize.x; ++x) {
      if (largestChannelDifference(pixelAt(withParticles, x, y), pixelAt(background, x, y)) <= kSnowThreshold) continue;
      ++coverage.pixels;
      coverage.minPx = glm::min(coverage.minPx, glm::ivec2(x, y));
      coverage.maxPx = glm::max(coverage.maxPx, glm::ivec2(x, y));
    }
  }
  return coverage;
}

// Mean colour of a rectangle of pixels.
glm::dvec3 meanColor(const Image& image, glm::dvec2 minPx, glm::dvec2 maxPx) {
  glm::dvec3 sum(0.0);
  int count = 0;
  for (int y = int(std::ceil(minPx.y)); y <= int(maxPx.y); ++y) {
    for (int x = int(std::ceil(minPx.x)); x <= int(maxPx.x); ++x) {
      const Pixel pixel = pixelAt(image, x, y);
      sum += glm::dvec3(pixel.r, pixel.g, pixel.b);
      ++count;
    }
  }
  return sum / double(std::max(count, 1));
}

class RenderTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { firn::test::glContext(); }
  static const firn::gl::ContextInfo& gl() { return firn::test::glContext().info(); }
};

// A box of snow covers what the camera's projection of the box predicts. The particles are spheres of their
// rest volume s³, radius r = (3 s³ / 4π)^(1/3) ≈ 0.62 s, around centres on a lattice half a spacing inside each
// face, jittered by ±0.25 s (engine/scene/Sampling.cpp): the picture's outline lies between 0.75 s − 0.62 s
// = 0.13 s inside the box's and 0.62 s − 0.25 s = 0.37 s outside it. So the snow's pixel count may differ
// from the projected area by at most perimeter × (0.37 s + 1 px), and the snow's bounding rectangle from the
// projected one by 0.37 s + 1 px on each side, s in pixels at the box's nearest corner and 1 px for sampling
// at pixel centres. Measured: area −0.5 %, bounds within 1 px, of budgets 12.6 % and 3.6 px.
TEST_F(RenderTest, SnowBoxCoversItsProjectedSilhouette) {
  const glm::dvec3 boxMinM(0.4, 0.5, 0.4), boxMaxM(0.6, 0.7, 0.6);
  const Scene scene = sceneFromJson("[" + box("[0.4, 0.5, 0.4]", "[0.6, 0.7, 0.6]") + "]");
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  Renderer renderer(scene);
  const Camera camera = cameraBelowBox();
  const Image background = renderFrame(renderer, nullptr, camera, ColorMode::Material);
  const Image snow = renderFrame(renderer, &simulation, camera, ColorMode::Material);

  const Silhouette predicted = boxSilhouette(camera, boxMinM, boxMaxM);
  const Coverage measured = snowCoverage(snow, background);
  const double spacingPx = kSpacingM * pixelsPerMetreAtNearestCorner(camera, boxMinM, boxMaxM);
  const double outlineTolerancePx = 0.37 * spacingPx + 1;
  const double imageArea = double(kImageSize.x) * kImageSize.y;
  ASSERT_GT(predicted.areaPx, 0.05 * imageArea) << "the box should fill a fair part of the picture";
  EXPECT_NEAR(measured.pixels / imageArea, predicted.areaPx / imageArea,
              predicted.perimeterPx * outlineTolerancePx / imageArea);
  // Pixel (x, y) is covered when its centre (x + ½, y + ½) is.
  EXPECT_NEAR(measured.minPx.x + 0.5, predicted.minPx.x, outlineTolerancePx);
  EXPECT_NEAR(measured.minPx.y + 0.5, predicted.minPx.y, outlineTolerancePx);
  EXPECT_NEAR(measured.maxPx.x + 0.5, predicted.maxPx.x, outlineTolerancePx);
  EXPECT_NEAR(measured.maxPx.y + 0.5, predicted.maxPx.y, outlineTolerancePx);

  EXPECT_EQ(renderFrame(renderer, nullptr, camera, ColorMode::Material).rgba, background.rgba)
      << "rendering is deterministic";

  // The front face, lit by the key and fill lights, is near-white with a touch of blue.
  const Silhouette frontFace = boxSilhouette(camera, {boxMinM.x, boxMinM.y, boxMaxM.z}, boxMaxM);
  const glm::dvec2 quarter = 0.25 * (frontFace.maxPx - frontFace.minPx);
  const glm::dvec3 front = meanColor(snow, frontFace.minPx + quarter, frontFace.maxPx - quarter);
  EXPECT_GT(front.r, 170) << "bright: the sky behind has 127";
  EXPECT_GE(front.b, front.r) << "bluish";
  EXPECT_LT(front.b - front.r, 30) << "only slightly";
}

// The same box drawn as its surface (RenderMode::Surface) covers its projected silhouette. Its faces lie where the
// particles' cells end: the volume fraction is ½ there (docs/surfaces.md), and the lattice fills this box exactly
// (16 spacings a side), so no face moves outwards beyond the jitter's ±¼ s, which the kernel of radius R = 3 s
// averages to a tenth of s. Its edges and corners are rounded: on an edge's bisector the fraction reaches ½ at
// 0.15 R inside each face (the M4 kernel, integrated numerically), so the outline moves inwards by up to 0.15 R √2
// = 0.21 R; on a corner's diagonal at 0.235 R inside each face, 0.41 R in all. With a pixel for sampling at pixel
// centres: the snow's pixels differ from the projected area by perimeter × (0.21 R + 1 px) inwards and perimeter ×
// (0.1 s + 1 px) outwards; no pixel deeper inside the outline than 0.41 R + 1 px shows the background, and none
// farther outside it than 0.1 s + 1 px shows snow; lengths in pixels at the box's nearest corner. Measured: 9.6%
// fewer pixels than projected, of a budget of 19%.
TEST_F(RenderTest, SnowSurfaceOfABoxCoversItsProjectedSilhouette) {
  const glm::dvec3 boxMinM(0.4, 0.5, 0.4), boxMaxM(0.6, 0.7, 0.6);
  const Scene scene = sceneFromJson("[" + box("[0.4, 0.5, 0.4]", "[0.6, 0.7, 0.6]") + "]");
  const std::vector<firn::ParticleSeed> seeds = firn::sampleBodies(scene);
  Simulation simulation(scene, seeds, gl());
  Renderer renderer(scene);
  firn::surface::SurfaceReconstruction surface(scene, seeds, gl());
  surface.reconstruct(simulation.particleView(), renderer.particleColors(simulation.particleView(), ColorMode::Material));
  const Camera camera = cameraBelowBox();
  const Image background = renderFrame(renderer, nullptr, camera, ColorMode::Material);
  const Image snow = renderFrame(renderer, &simulation, camera, ColorMode::Material, &surface);

  const Silhouette predicted = boxSilhouette(camera, boxMinM, boxMaxM);
  const Coverage measured = snowCoverage(snow, background);
  const double pxPerM = pixelsPerMetreAtNearestCorner(camera, boxMinM, boxMaxM);
  const double kernelRadiusM = scene.surface.smoothing * kSpacingM;
  const double inwardPx = 0.21 * kernelRadiusM * pxPerM + 1, outwardPx = 0.1 * kSpacingM * pxPerM + 1;
  const double cornerInwardPx = 0.41 * kernelRadiusM * pxPerM + 1;
  EXPECT_GT(measured.pixels, predicted.areaPx - predicted.perimeterPx * inwardPx);
  EXPECT_LT(measured.pixels, predicted.areaPx + predicted.perimeterPx * outwardPx);
  int uncoveredInside = 0, coveredOutside = 0, deepInside = 0;
  for (int y = 0; y < kImageSize.y; ++y) {
    for (int x = 0; x < kImageSize.x; ++x) {
      const double distancePx = signedDistanceToHull(predicted.hullPx, {x + 0.5, y + 0.5});
      const bool covered = largestChannelDifference(pixelAt(snow, x, y), pixelAt(background, x, y)) > kSnowThreshold;
      deepInside += distancePx < -cornerInwardPx;
      uncoveredInside += !covered && distancePx < -cornerInwardPx;
      coveredOutside += covered && distancePx > outwardPx;
    }
  }
  EXPECT_GT(deepInside, predicted.areaPx / 2) << "most of the silhouette is farther inside than the rounding";
  EXPECT_EQ(uncoveredInside, 0);
  EXPECT_EQ(coveredOutside, 0);

  // The lit front face reads as snow: bright and a little blue, as the particles' does.
  const Silhouette frontFace = boxSilhouette(camera, {boxMinM.x, boxMinM.y, boxMaxM.z}, boxMaxM);
  const glm::dvec2 quarter = 0.25 * (frontFace.maxPx - frontFace.minPx);
  const glm::dvec3 front = meanColor(snow, frontFace.minPx + quarter, frontFace.maxPx - quarter);
  EXPECT_GT(front.r, 170) << "bright: the sky behind has 127";
  EXPECT_GE(front.b, front.r) << "bluish";
}

// Without particles the picture is the sky, the ground and the colliders: every pixel opaque and finite
// (a NaN in a shader's output would be stored as black), none as bright as lit snow, the sphere collider's
// colour where the sphere is and sky above the scene.
TEST_F(RenderTest, FrameWithoutParticlesShowsOnlyBackgroundAndColliders) {
  const Scene scene = sceneFromJson("[" + box("[0.4, 0.5, 0.4]", "[0.6, 0.7, 0.6]") + "]", R"([
      { "type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0], "friction": 0.3 },
      { "type": "sphere", "center": [0.35, 0.3, 0.5], "radius": 0.12 },
      { "type": "box", "min": [0.6, 0.1, 0.4], "max": [0.8, 0.3, 0.6] } ])");
  Renderer renderer(scene);
  const Camera camera = firn::render::defaultCamera(scene, float(kImageSize.x) / float(kImageSize.y));
  const Image image = renderFrame(renderer, nullptr, camera, ColorMode::Material);

  int black = 0, translucent = 0, snowWhite = 0;
  for (int y = 0; y < kImageSize.y; ++y) {
    for (int x = 0; x < kImageSize.x; ++x) {
      const Pixel pixel = pixelAt(image, x, y);
      black += pixel.r == 0 && pixel.g == 0 && pixel.b == 0;
      translucent += pixel.a != 255;
      snowWhite += std::min({pixel.r, pixel.g, pixel.b}) > 235;
    }
  }
  EXPECT_EQ(black, 0);
  EXPECT_EQ(translucent, 0);
  EXPECT_EQ(snowWhite, 0);

  const glm::dvec2 sphereCentrePx = projectToPixels(camera, {0.35, 0.3, 0.5});
  const Pixel sphere = pixelAt(image, int(sphereCentrePx.x), int(sphereCentrePx.y));
  EXPECT_GT(sphere.r, sphere.b + 20) << "the sphere collider is terracotta";
  const Pixel sky = pixelAt(image, kImageSize.x / 2, 0);
  EXPECT_GT(sky.b, sky.r + 20) << "the sky is blue";
}

// Speed colouring tells a moving body from a still one that Material colouring shows alike: the still box
// takes the bottom of viridis (dark purple), the box at 3 m/s (⅔ of the scale √(2 g · 1 m) = 4.4 m/s) its
// green part, drawn as particles or as their surface. Compared over the inner half of each box's projected
// rectangle, away from edges.
TEST_F(RenderTest, SpeedModeColoursMovingBodyDifferently) {
  const Scene scene = sceneFromJson("[" + box("[0.25, 0.5, 0.4]", "[0.45, 0.7, 0.6]") + ", " +
                                    box("[0.55, 0.5, 0.4]", "[0.75, 0.7, 0.6]", "[3, 0, 0]") + "]");
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  Renderer renderer(scene);
  EXPECT_NEAR(renderer.speedScaleMPerS(), std::sqrt(2 * 9.81 * 1.0), 1e-3);
  Camera camera = cameraBelowBox();
  camera.positionM = {0.5f, 0.3f, 1.35f};

  auto innerMean = [&](const Image& image, const glm::dvec3& minM, const glm::dvec3& maxM) {
    const Silhouette silhouette = boxSilhouette(camera, minM, maxM);
    const glm::dvec2 quarter = 0.25 * (silhouette.maxPx - silhouette.minPx);
    return meanColor(image, silhouette.minPx + quarter, silhouette.maxPx - quarter);
  };
  const glm::dvec3 stillMinM(0.25, 0.5, 0.4), stillMaxM(0.45, 0.7, 0.6);
  const glm::dvec3 movingMinM(0.55, 0.5, 0.4), movingMaxM(0.75, 0.7, 0.6);

  const Image material = renderFrame(renderer, &simulation, camera, ColorMode::Material);
  const glm::dvec3 stillMaterial = innerMean(material, stillMinM, stillMaxM);
  const glm::dvec3 movingMaterial = innerMean(material, movingMinM, movingMaxM);
  // Same material, similar lighting: within 20 of 255 per channel (shading differs a little with the angle).
  for (int channel = 0; channel < 3; ++channel) EXPECT_NEAR(stillMaterial[channel], movingMaterial[channel], 20);

  const Image speed = renderFrame(renderer, &simulation, camera, ColorMode::Speed);
  const glm::dvec3 still = innerMean(speed, stillMinM, stillMaxM);
  const glm::dvec3 moving = innerMean(speed, movingMinM, movingMaxM);
  EXPECT_GT(moving.g, still.g + 60) << "viridis turns green with speed";
  EXPECT_GT(still.b, still.g) << "viridis starts purple";
  EXPECT_GT(glm::length(moving - still), 80);

  // Drawn as their surface, the boxes carry the same colours: the particles' albedo interpolated onto it.
  firn::surface::SurfaceReconstruction surface(scene, firn::sampleBodies(scene), gl());
  surface.reconstruct(simulation.particleView(), renderer.particleColors(simulation.particleView(), ColorMode::Speed));
  const Image speedSurface = renderFrame(renderer, &simulation, camera, ColorMode::Speed, &surface);
  const glm::dvec3 stillSurface = innerMean(speedSurface, stillMinM, stillMaxM);
  const glm::dvec3 movingSurface = innerMean(speedSurface, movingMinM, movingMaxM);
  EXPECT_GT(movingSurface.g, stillSurface.g + 60) << "viridis turns green with speed";
  EXPECT_GT(stillSurface.b, stillSurface.g) << "viridis starts purple";
}

// The domain's box is outlined only on request: a renderer draws none by default, and with setDomainEdges(true)
// the picture changes along the projected edges of the domain's interior (where the walls stop the snow) and nowhere
// else (within 1.5 px of a segment: a one-pixel
// line rasterised about its exact projection). The camera sees the whole 1 m domain from outside it.
TEST_F(RenderTest, DomainBoxIsDrawnOnlyOnRequest) {
  const Scene scene = sceneFromJson("[" + box("[0.4, 0.5, 0.4]", "[0.6, 0.7, 0.6]") + "]");
  Camera camera;
  camera.positionM = {0.5f, 1.2f, 3.0f};
  camera.targetM = {0.5f, 0.45f, 0.5f};
  camera.fovDeg = 40;
  firn::render::fitDepthRange(camera, scene);
  Renderer renderer(scene);
  EXPECT_FALSE(renderer.domainEdges());
  const Image plain = renderFrame(renderer, nullptr, camera, ColorMode::Material);
  renderer.setDomainEdges(true);
  const Image outlined = renderFrame(renderer, nullptr, camera, ColorMode::Material);

  std::vector<std::pair<glm::dvec2, glm::dvec2>> edgesPx;
  for (int from = 0; from < 8; ++from) {
    for (int bit : {1, 2, 4}) {
      if (from & bit) continue;
      const auto cornerM = [&](int index) {
        return glm::mix(scene.grid.interiorMinM(), scene.grid.interiorMaxM(),
                        glm::dvec3(index & 1, (index >> 1) & 1, (index >> 2) & 1));
      };
      edgesPx.emplace_back(projectToPixels(camera, cornerM(from)), projectToPixels(camera, cornerM(from | bit)));
    }
  }
  int changed = 0, changedAwayFromEdges = 0;
  for (int y = 0; y < kImageSize.y; ++y) {
    for (int x = 0; x < kImageSize.x; ++x) {
      if (largestChannelDifference(pixelAt(plain, x, y), pixelAt(outlined, x, y)) == 0) continue;
      ++changed;
      const glm::dvec2 point(x + 0.5, y + 0.5);
      double nearestPx = 1e9;
      for (const auto& [a, b] : edgesPx) {
        const glm::dvec2 edge = b - a;
        const double along = glm::clamp(glm::dot(point - a, edge) / glm::dot(edge, edge), 0.0, 1.0);
        nearestPx = std::min(nearestPx, glm::length(point - (a + along * edge)));
      }
      changedAwayFromEdges += nearestPx > 1.5;
    }
  }
  // The box's visible edges run several hundred pixels at this size; the ones hidden by the ground change nothing.
  EXPECT_GT(changed, 300);
  EXPECT_EQ(changedAwayFromEdges, 0);
}

// A mesh collider (a cube given as triangles, as a loaded file gives them) and a rigid ball drawn at the pose the
// caller passes, not where the scene starts it. The ball's ochre lies within its projected outline at that pose
// and nowhere else, and none is drawn without a pose; the collider's terracotta covers its top face. Each darkens
// the ground where the key light's ray past it falls (render/ground.glsl's shadowPoint), against the same picture
// without it.
TEST_F(RenderTest, MeshColliderAndPosedRigidBodyAreDrawnWithShadows) {
  const glm::dvec3 cubeMinM(0.15, 0.1, 0.45), cubeMaxM(0.3, 0.25, 0.6);
  auto cube = std::make_shared<firn::voxelizer::TriangleMesh>();
  for (int corner = 0; corner < 8; ++corner) {
    const glm::dvec3 upper(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1);
    cube->vertices.push_back(glm::mix(cubeMinM, cubeMaxM, upper));
  }
  // Outward, counter-clockwise from outside: −x, +x, −y, +y, −z, +z.
  const unsigned faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  for (const auto& face : faces) {
    cube->triangles.emplace_back(face[0], face[1], face[2]);
    cube->triangles.emplace_back(face[0], face[2], face[3]);
  }
  const Scene withoutObjects = sceneFromJson("[" + box("[0.8, 0.5, 0.8]", "[0.9, 0.6, 0.9]") + "]",
                                             R"([{ "type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0] }])");
  Scene scene = withoutObjects;
  firn::Collider meshCollider;
  meshCollider.shape = firn::ColliderShape::Mesh;
  meshCollider.mesh = cube;
  meshCollider.pivotM = 0.5 * (cubeMinM + cubeMaxM);
  scene.colliders.push_back(meshCollider);
  firn::RigidBody ball;
  ball.shape = firn::RigidShape::Sphere;
  ball.radiusM = 0.06;
  ball.centerM = ball.centerOfMassM = {0.5, 0.7, 0.5};
  scene.rigidBodies.push_back(ball);
  firn::ObjectPose ballPose;
  ballPose.positionM = {0.6, 0.35, 0.6};

  Camera camera;
  camera.positionM = {0.5f, 1.5f, 1.0f};
  camera.targetM = {0.5f, 0.1f, 0.45f};
  camera.fovDeg = 40;
  firn::render::fitDepthRange(camera, scene);
  Renderer renderer(scene);
  Renderer bareRenderer(withoutObjects);
  const auto render = [&](Renderer& drawing, const std::vector<firn::ObjectPose>& poses) {
    firn::gl::Framebuffer target(kImageSize);
    target.bind();
    drawing.draw(firn::ParticleView{}, poses, camera, kImageSize, ColorMode::Material);
    Image image{kImageSize.x, kImageSize.y, target.readColorRgba8()};
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    return image;
  };
  const Image posed = render(renderer, {ballPose});
  const Image unposed = render(renderer, {});
  const Image bare = render(bareRenderer, {});

  // Lit ochre's green exceeds its blue by 113 levels at the ball's centre (measured), terracotta's by 23 and the
  // ground's by 11; the ball's shaded side keeps more than 60.
  const auto isOchre = [](const Pixel& pixel) { return pixel.g - pixel.b > 60; };
  std::vector<glm::dvec2> ballOutline;
  for (int i = 0; i < 400; ++i) {
    // A Fibonacci sphere: points spread evenly over the ball, whose projections' hull is its outline.
    const double y = 1 - (i + 0.5) / 200.0, ring = std::sqrt(1 - y * y), angle = 2.39996323 * i;
    ballOutline.push_back(projectToPixels(
        camera, ballPose.positionM + ball.radiusM * glm::dvec3(ring * std::cos(angle), y, ring * std::sin(angle))));
  }
  const std::vector<glm::dvec2> ballHull = convexHull(ballOutline);
  int ochre = 0, ochreOutside = 0, ochreUnposed = 0;
  for (int y = 0; y < kImageSize.y; ++y) {
    for (int x = 0; x < kImageSize.x; ++x) {
      if (isOchre(pixelAt(unposed, x, y))) ++ochreUnposed;
      if (!isOchre(pixelAt(posed, x, y))) continue;
      ++ochre;
      // The 400 points' hull lies within a few tenths of a pixel inside the true outline here; 1 px in all, with
      // sampling at pixel centres.
      ochreOutside += signedDistanceToHull(ballHull, {x + 0.5, y + 0.5}) > 1.0;
    }
  }
  // The ball's outline covers about 900 pixels (measured: 826 of them ochre, its darkest rim not).
  EXPECT_GT(ochre, 600);
  EXPECT_EQ(ochreOutside, 0);
  EXPECT_EQ(ochreUnposed, 0) << "a body without a pose is not drawn";

  const glm::dvec2 topPx = projectToPixels(camera, 0.5 * (cubeMinM + cubeMaxM) + glm::dvec3(0, 0.075, 0));
  const Pixel top = pixelAt(posed, int(topPx.x), int(topPx.y));
  EXPECT_GT(top.r, top.b + 20) << "the mesh collider is terracotta";
  EXPECT_FALSE(isOchre(top));

  // Where the key light's ray past a point meets the ground (y = 0.1; render/lighting.glsl's direction): under the
  // ball's centre, and under the cube's top face beyond its footprint. An object's shadow is opaque
  // (collider_shadow.frag), leaving the ground only ambient and fill light: measured 44–70 levels darker per channel.
  const glm::dvec3 toLight = glm::normalize(glm::dvec3(-0.45, 0.8, 0.4));
  const glm::dvec3 ballShadowM = ballPose.positionM - toLight * ((ballPose.positionM.y - 0.1) / toLight.y);
  for (const glm::dvec3& groundM : {ballShadowM, glm::dvec3(0.34, 0.1, 0.41)}) {
    const glm::dvec2 px = projectToPixels(camera, groundM);
    const Pixel shadowed = pixelAt(posed, int(px.x), int(px.y)), open = pixelAt(bare, int(px.x), int(px.y));
    EXPECT_LT(shadowed.r + shadowed.g + shadowed.b + 3 * 30, open.r + open.g + open.b)
        << "no shadow at (" << groundM.x << ", " << groundM.z << ")";
  }

  // A file's triangles may wind inward: the renderer lights the side it sees, so the cube looks the same (to within
  // a level of rounding) wound either way.
  auto inwardCube = std::make_shared<firn::voxelizer::TriangleMesh>(*cube);
  for (glm::uvec3& triangle : inwardCube->triangles) std::swap(triangle.y, triangle.z);
  Scene inward = scene;
  inward.colliders.back().mesh = inwardCube;
  Renderer inwardRenderer(inward);
  const Pixel inwardTop = pixelAt(render(inwardRenderer, {ballPose}), int(topPx.x), int(topPx.y));
  EXPECT_LE(largestChannelDifference(inwardTop, top), 1);
}

// In surface mode a body shades the snow under it through the key light's shadow map, even from above the box the
// map covers (the snow's bounds): the snow's top where the light's ray past the ball's centre meets it is darker
// with the ball than without it. Measured: 238 → 178 in red; a third of that drop is asked for.
TEST_F(RenderTest, SnowSurfaceIsShadedByABodyAboveIt) {
  Scene scene = sceneFromJson("[" + box("[0.3, 0.1, 0.3]", "[0.7, 0.25, 0.7]") + "]",
                              R"([{ "type": "plane", "point": [0, 0.1, 0], "normal": [0, 1, 0] }])");
  firn::RigidBody ball;
  ball.shape = firn::RigidShape::Sphere;
  ball.radiusM = 0.08;
  ball.centerM = ball.centerOfMassM = {0.5, 0.4, 0.5};
  scene.rigidBodies.push_back(ball);
  const std::vector<firn::ParticleSeed> seeds = firn::sampleBodies(scene);
  Simulation simulation(scene, seeds, gl());
  Renderer renderer(scene);
  firn::surface::SurfaceReconstruction surface(scene, seeds, gl());
  const firn::ParticleView particles = simulation.particleView();
  surface.reconstruct(particles, renderer.particleColors(particles, ColorMode::Material));
  Camera camera;
  camera.positionM = {0.5f, 1.2f, 1.5f};
  camera.targetM = {0.5f, 0.2f, 0.5f};
  camera.fovDeg = 40;
  firn::render::fitDepthRange(camera, scene);
  const auto render = [&](const std::vector<firn::ObjectPose>& poses) {
    firn::gl::Framebuffer target(kImageSize);
    target.bind();
    renderer.draw(simulation.particleView(), poses, camera, kImageSize, ColorMode::Material, &surface);
    Image image{kImageSize.x, kImageSize.y, target.readColorRgba8()};
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    return image;
  };
  const Image withBall = render({firn::initialBodyPose(ball)});
  const Image withoutBall = render({});

  const glm::dvec3 toLight = glm::normalize(glm::dvec3(-0.45, 0.8, 0.4));  // render/lighting.glsl
  const glm::dvec3 snowTopM = ball.centerM - toLight * ((ball.centerM.y - 0.25) / toLight.y);
  const glm::dvec2 px = projectToPixels(camera, snowTopM);
  const Pixel shaded = pixelAt(withBall, int(px.x), int(px.y)), lit = pixelAt(withoutBall, int(px.x), int(px.y));
  EXPECT_GT(lit.r, 200) << "lit snow";
  EXPECT_LT(shaded.r, lit.r - 20);
}

// writePng writes a PNG that a reader decodes to the same pixels, and a path it cannot write is an
// InputError that names the file.
TEST_F(RenderTest, WritePngRoundTripsPixels) {
  const Scene scene = sceneFromJson("[" + box("[0.4, 0.5, 0.4]", "[0.6, 0.7, 0.6]") + "]");
  Simulation simulation(scene, firn::sampleBodies(scene), gl());
  firn::render::OffscreenRenderer offscreen(scene, {96, 64});
  const Image image = offscreen.render(simulation.particleView(), simulation.rigidBodyPoses(), cameraBelowBox(),
                                       ColorMode::Material);
  ASSERT_EQ(image.rgba.size(), std::size_t(96 * 64 * 4));

  const std::filesystem::path directory =
      std::filesystem::temp_directory_path() / ("firn_render_test_" + std::to_string(getpid()));
  std::filesystem::create_directories(directory);
  const std::filesystem::path path = directory / "frame.png";
  firn::render::writePng(path, image);
  int width = 0, height = 0, channels = 0;
  stbi_uc* decoded = stbi_load(path.c_str(), &width, &height, &channels, 4);
  ASSERT_NE(decoded, nullptr) << stbi_failure_reason();
  EXPECT_EQ(width, 96);
  EXPECT_EQ(height, 64);
  EXPECT_TRUE(std::equal(image.rgba.begin(), image.rgba.end(), decoded));
  stbi_image_free(decoded);
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".part"));

  const std::filesystem::path unwritable = directory / "absent" / "frame.png";
  try {
    firn::render::writePng(unwritable, image);
    ADD_FAILURE() << "expected InputError";
  } catch (const firn::InputError& error) {
    EXPECT_NE(std::string(error.what()).find(unwritable.string()), std::string::npos) << error.what();
  }
  std::filesystem::remove_all(directory);
}

}  // namespace
