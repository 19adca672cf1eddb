#version 430 core
// A collider or rigid body is opaque: its shadow has the optical depth of a fully dark one (e^−8 of the key light
// left).
out float opticalDepth;

void main() { opticalDepth = 8.0; }
