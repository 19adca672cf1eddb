#pragma once
// The experiments of `firn bench`, one file each: each measures what its file's header says, writes its table
// (DIR/<table>.csv, tableNames()) and adds its findings to the summary; its plan… function counts, from the run's
// sizes alone, what it will build and step (the estimate `firn bench` prints before it starts).
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

PlannedWork planParticles(const BenchRun& run);
PlannedWork planGrid(const BenchRun& run);
PlannedWork planDomain(const BenchRun& run);
PlannedWork planPasses(const BenchRun& run);
PlannedWork planP2GAtomics(const BenchRun& run);
PlannedWork planTradeoff(const BenchRun& run);
PlannedWork planStiff(const BenchRun& run);
PlannedWork planThesis(const BenchRun& run);
PlannedWork planSurface(const BenchRun& run);
PlannedWork planObjects(const BenchRun& run);

}  // namespace firn::bench
