// The per-particle buffers, mirroring engine/sim/GpuLayout.h: declared here alone, with nothing
// compute-only, so that the simulation's passes and the renderer's vertex shader share one declaration.
// Binding points come from the host as FIRN_BINDING_* defines.

layout(std430, binding = FIRN_BINDING_POSITION_MASS) buffer PositionMassBuffer { vec4 positionMass[]; };
layout(std430, binding = FIRN_BINDING_VELOCITY_VOLUME) buffer VelocityVolumeBuffer { vec4 velocityVolume[]; };
#ifdef FIRN_HAS_DEFORMATION_GRADIENT
layout(std430, binding = FIRN_BINDING_ELASTIC_DEFORMATION) buffer ElasticDeformationBuffer { mat3 elasticDeformation[]; };
#endif
layout(std430, binding = FIRN_BINDING_KIRCHHOFF_STRESS) buffer KirchhoffStressBuffer { mat3 kirchhoffStress[]; };
#ifdef FIRN_TRANSFER_APIC
layout(std430, binding = FIRN_BINDING_AFFINE) buffer AffineBuffer { mat3 affine[]; };
#endif

struct PlasticState {
  float plasticJ;          // snow: J_P = det F_P; water: J = det F; sand: hardening state q
  uint materialIndex;
  float volumeCorrection;  // sand: V_c, the log-volume correction (Klár 2016)
  float unused;
};
layout(std430, binding = FIRN_BINDING_PLASTIC_STATE) buffer PlasticStateBuffer { PlasticState plasticState[]; };
