// SPDX-License-Identifier: GPL-3.0-or-later
// nscdBench state: the contact solver methods (System::Settings::Method) on
// a grain state saved by a run (the grainState.h5 of a time directory, read
// by System::readHDF5 with its contact impulses, i.e. warm-started as the run
// would be), stepped without the fluid for a few steps with each method, one
// core, thread CPU time. Tolerance and maxIterations are the run's (saved in
// the state) unless given. Used by tests/bench/contactMethods on the moving
// beds of the tutorials (Rayleigh-Taylor, droplet bed).
//   nscdBench state <grainState.h5> <dt [s]> <steps> <out.json> [tolerance [maxIterations]]
#include "benchBeds.H"

#include <cstdio>
#include <fstream>
#include <sstream>

using namespace nscd;
using namespace nscdBench;

namespace
{
struct Method
{
    const char* name;
    System::Settings::Method method;
    double relaxation;
};
} // namespace

int runState(int argc, char** argv)
{
    if (argc < 6)
    {
        std::fprintf(
            stderr,
            "usage: nscdBench state <grainState.h5> <dt> <steps> <out.json> [tolerance [maxIterations]]\n");
        return 2;
    }
    const std::string file = argv[2];
    const double h = std::atof(argv[3]);
    const int steps = std::atoi(argv[4]);
    const std::string out = argv[5];
    std::setvbuf(stderr, nullptr, _IOLBF, 0);
    using M = System::Settings::Method;
    const std::vector<Method> methods = {{"NLGS", M::NLGS, 1.0},
                                         {"overRelaxedNLGS", M::OverRelaxedNLGS, 1.3},
                                         {"APGD", M::APGD, 1.0},
                                         {"NNCG", M::NNCG, 1.0}};
    std::vector<std::string> rows;
    double tol = 0;
    int maxIt = 0;
    std::size_t grains = 0;
    for (const Method& m : methods)
    {
        System s = System::readHDF5(file);
        if (argc > 6) s.settings().tolerance = std::atof(argv[6]);
        if (argc > 7) s.settings().maxIterations = std::atoi(argv[7]);
        tol = s.settings().tolerance;
        maxIt = s.settings().maxIterations;
        grains = s.size();
        s.settings().method = m.method;
        s.settings().relaxation = m.relaxation;
        std::vector<double> cpuStep, sweeps, residual, hist;
        int contacts = 0;
        bool conv = true;
        for (int k = 0; k < steps; ++k)
        {
            s.settings().residualHistory = k == 0; // the first step's history (its cost is not timed apart)
            const double c0 = cpu();
            const StepReport r = s.step(h);
            cpuStep.push_back(cpu() - c0);
            sweeps.push_back(r.sweeps);
            residual.push_back(r.residual);
            conv = conv && r.converged;
            contacts = r.contacts;
            if (k == 0) hist = r.residualHistory;
        }
        std::fprintf(
            stderr,
            "  [%s] %zu grains, %d contacts: sweeps/step %s, CPU s/step %s (first step with history)\n",
            m.name, s.size(), contacts, jsonList(sweeps).c_str(), jsonList(cpuStep).c_str());
        std::ostringstream o;
        o << "{\"method\": \"" << m.name << "\", \"relaxation\": " << m.relaxation
          << ", \"contacts\": " << contacts << ", \"sweeps_per_step\": " << jsonList(sweeps)
          << ", \"cpu_seconds_per_step\": " << jsonList(cpuStep)
          << ", \"residual_per_step\": " << jsonList(residual)
          << ", \"converged_every_step\": " << (conv ? "true" : "false")
          << ", \"residual_history_step_1\": " << jsonList(hist) << "}";
        rows.push_back(o.str());
    }
    std::ofstream o(out);
    o << "{\n  \"state\": \"" << file << "\",\n  \"grains\": " << grains << ",\n  \"dt\": " << h
      << ",\n  \"steps\": " << steps << ",\n  \"tolerance_over_dmin\": " << tol
      << ",\n  \"max_iterations\": " << maxIt << ",\n  \"machine\": \"" << machineNote()
      << "\",\n  \"what\": \"the saved state stepped without the fluid (gravity "
      << "and contacts only), warm-started from its saved impulses; CPU seconds of the thread per step (the "
         "first step "
      << "records the residual history, one residual evaluation per sweep or iteration, included in its "
         "time)\",\n"
      << "  \"methods\": [\n    ";
    for (std::size_t k = 0; k < rows.size(); ++k) o << (k ? ",\n    " : "") << rows[k];
    o << "\n  ]\n}\n";
    std::fprintf(stderr, "wrote %s\n", out.c_str());
    return 0;
}
