// The per-particle buffers (common/gpu_contract.h): declared here alone, with nothing compute-only, so that the
// simulation's passes and the renderer's vertex shader share one declaration. Passes over the grid alone define
// FIRN_WITHOUT_PARTICLE_BUFFERS before their includes: llvmpipe counts every storage block a shader declares, used
// or not, against its 16 (docs/platform.md).
#include "common/gpu_contract.h"

#ifndef FIRN_WITHOUT_PARTICLE_BUFFERS

layout(std430, binding = FIRN_BINDING_POSITION_MASS) buffer PositionMassBuffer { vec4 positionMass[]; };
layout(std430, binding = FIRN_BINDING_VELOCITY_VOLUME) buffer VelocityVolumeBuffer { vec4 velocityVolume[]; };
#ifdef FIRN_HAS_DEFORMATION_GRADIENT
layout(std430, binding = FIRN_BINDING_ELASTIC_DEFORMATION) buffer ElasticDeformationBuffer { mat3 elasticDeformation[]; };
#endif
layout(std430, binding = FIRN_BINDING_KIRCHHOFF_STRESS) buffer KirchhoffStressBuffer { mat3 kirchhoffStress[]; };
#if defined(FIRN_TRANSFER_APIC) && !defined(FIRN_WITHOUT_AFFINE)
layout(std430, binding = FIRN_BINDING_AFFINE) buffer AffineBuffer { mat3 affine[]; };
#endif

layout(std430, binding = FIRN_BINDING_PLASTIC_STATE) buffer PlasticStateBuffer { ParticlePlasticState plasticState[]; };
#endif
