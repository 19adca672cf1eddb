#pragma once
// The experiments of `firn bench`, one file each: each measures what its file's header says, writes its table
// (DIR/<table>.csv, tableNames()) and adds its findings to the summary.
#include "BenchRun.h"

namespace firn::bench {

void measureParticles(BenchRun& run);   // particles.csv (ParticlesExperiment.cpp)
void measureGrid(BenchRun& run);        // grid.csv (GridExperiment.cpp)
void measureDomain(BenchRun& run);      // domain.csv (DomainExperiment.cpp)
void measurePasses(BenchRun& run);      // passes.csv (PassesExperiment.cpp)
void measureP2GAtomics(BenchRun& run);  // p2g_atomics.csv (P2GAtomicsExperiment.cpp)
void measureTradeoff(BenchRun& run);    // tradeoff.csv (TradeoffExperiment.cpp)
void measureStiff(BenchRun& run);       // stiff.csv (StiffExperiment.cpp)
void measureThesis(BenchRun& run);      // thesis.csv (ThesisExperiment.cpp)
void measureSurface(BenchRun& run);     // surface.csv (SurfaceExperiment.cpp)
void measureObjects(BenchRun& run);     // objects.csv (ObjectsExperiment.cpp)

}  // namespace firn::bench
