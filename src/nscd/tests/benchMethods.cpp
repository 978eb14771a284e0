// SPDX-License-Identifier: GPL-3.0-or-later
// nscdBench methods: the contact solver methods (System::Settings::Method)
// compared on the beds of tests/bench/nscdDeposit, one core:
//  - settling the 500-disc block from the loose lattice (mu = 0.4), to rest
//    with the suite's criterion (benchSuite.cpp, settle);
//  - the 70,000-disc bed at rest (mirror tiling of the NLGS-settled block,
//    relaxed 300 NLGS steps, saved), the same state stepped by each method.
// Times are thread CPU seconds (CLOCK_THREAD_CPUTIME_ID). Each case also
// records the residual history of one step (System::Settings::residualHistory,
// not timed). Writes a JSON object (merged into nscdDeposit.json by the script).
#include "benchBeds.H"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

using namespace nscd;
using namespace nscdBench;

namespace
{

struct Config
{
    const char* name;
    System::Settings::Method method;
    double relaxation;
};

void use(System& s, const Config& c)
{
    s.settings().method = c.method;
    s.settings().relaxation = c.relaxation;
    s.settings().maxIterations = 1000; // production cap (README)
}

/// one step with the residual history recorded (not timed)
std::vector<double> history(System& s)
{
    s.settings().residualHistory = true;
    std::vector<double> h = s.step(dt).residualHistory;
    s.settings().residualHistory = false;
    return h;
}

std::string settleJson(const Config& c, const Bed& b0, int maxSteps)
{
    System s = makeBlock(b0, 0.4);
    use(s, c);
    long sweeps = 0;
    int calm = 0, phase = 1, steps = 0, coarse = 0;
    bool rest = false, conv = true;
    double maxOv = 0;
    std::vector<double> hist;
    const double c0 = cpu();
    for (int k = 0; k < maxSteps; ++k)
    {
        if (k == 100)
        {
            hist = history(s);
            steps += 1;
            continue;
        } // not counted in sweeps
        const StepReport r = s.step(dt);
        sweeps += r.sweeps;
        steps = k + 1;
        conv = conv && r.converged;
        maxOv = std::max(maxOv, r.maxOverlap);
        const double v = vmax(s);
        calm = v < (phase == 1 ? 1.0 : 0.1) * g * dt ? calm + 1 : 0;
        if (phase == 1 && calm >= 20)
        {
            phase = 2;
            calm = 0;
            coarse = k + 1;
        }
        else if (phase == 2 && calm >= 50)
        {
            rest = true;
            break;
        }
    }
    const double sec = cpu() - c0;
    std::fprintf(stderr, "  [settle %s %.2f] %d steps, %.1f sweeps/step, %.2f CPU s, rest %d\n", c.name,
                 c.relaxation, steps, double(sweeps) / std::max(1, steps - 1), sec, int(rest));
    std::ostringstream o;
    o << "{\"method\": \"" << c.name << "\", \"relaxation\": " << c.relaxation << ", \"steps\": " << steps
      << ", \"steps_to_vmax_below_g_dt\": " << coarse
      << ", \"sweeps_per_step_mean\": " << double(sweeps) / std::max(1, steps - 1)
      << ", \"cpu_seconds\": " << sec << ", \"cpu_seconds_per_step\": " << sec / std::max(1, steps)
      << ", \"reached_rest\": " << (rest ? "true" : "false")
      << ", \"converged_every_step\": " << (conv ? "true" : "false")
      << ", \"max_overlap_over_rmin\": " << maxOv / (0.5 * dMin)
      << ", \"residual_history_step_100\": " << jsonList(hist) << "}";
    return o.str();
}

std::string restJson(const Config& c, const std::string& state, int timed, double budget)
{
    System s = System::readHDF5(state);
    use(s, c);
    std::vector<double> t, sw;
    bool conv = true;
    double maxOv = 0, res = 0;
    int contacts = 0;
    const double c0 = cpu();
    for (int k = 0; k < timed; ++k)
    {
        const double a = cpu();
        const StepReport r = s.step(dt);
        t.push_back(cpu() - a);
        sw.push_back(r.sweeps);
        conv = conv && r.converged;
        maxOv = std::max(maxOv, r.maxOverlap);
        res = std::max(res, r.residual);
        contacts = r.contacts;
        if (cpu() - c0 > budget && k >= 4) break;
    }
    const std::vector<double> hist = history(s);
    std::fprintf(stderr, "  [rest %s %.2f] %zu grains: %.4f CPU s/step median, %.1f sweeps/step\n", c.name,
                 c.relaxation, s.size(), median(t), median(sw));
    std::ostringstream o;
    o << "{\"method\": \"" << c.name << "\", \"relaxation\": " << c.relaxation << ", \"grains\": " << s.size()
      << ", \"contacts\": " << contacts << ", \"timed_steps\": " << t.size()
      << ", \"cpu_seconds_per_step_median\": " << median(t)
      << ", \"cpu_seconds_per_step_max\": " << *std::max_element(t.begin(), t.end())
      << ", \"sweeps_per_step_median\": " << median(sw) << ", \"max_residual\": " << res
      << ", \"converged_every_step\": " << (conv ? "true" : "false")
      << ", \"max_overlap_over_rmin\": " << maxOv / (0.5 * dMin) << ", \"vmax_end_m_per_s\": " << vmax(s)
      << ", \"residual_history\": " << jsonList(hist) << "}";
    return o.str();
}
} // namespace

int runMethods(int argc, char** argv)
{
    const std::string out = argc > 2 ? argv[2] : "nscdDepositMethods.json";
    const bool quick = argc > 3 && std::string(argv[3]) == "quick";
    std::setvbuf(stderr, nullptr, _IOLBF, 0);
    using M = System::Settings::Method;
    const std::vector<Config> configs = {{"NLGS", M::NLGS, 1.0},
                                         {"overRelaxedNLGS", M::OverRelaxedNLGS, 1.2},
                                         {"overRelaxedNLGS", M::OverRelaxedNLGS, 1.3},
                                         {"overRelaxedNLGS", M::OverRelaxedNLGS, 1.4},
                                         {"overRelaxedNLGS", M::OverRelaxedNLGS, 1.6},
                                         {"APGD", M::APGD, 1.0},
                                         {"NNCG", M::NNCG, 1.0}};
    const int blockN = 500, ncol = 8, nBig = quick ? 4 : 140, maxSettle = 3000;
    const Bed b0 = lattice(2, blockN, ncol, 1);
    std::vector<std::string> settleRows;
    for (const Config& c : configs) settleRows.push_back(settleJson(c, b0, maxSettle));
    // the bed at rest: tiles of the NLGS-settled block (as the suite), relaxed with NLGS
    System blk = makeBlock(b0, 0.4);
    for (int k = 0, calm = 0, phase = 1; k < maxSettle; ++k)
    {
        blk.step(dt);
        const double v = vmax(blk);
        calm = v < (phase == 1 ? 1.0 : 0.1) * g * dt ? calm + 1 : 0;
        if (phase == 1 && calm >= 20)
        {
            phase = 2;
            calm = 0;
        }
        else if (phase == 2 && calm >= 50)
            break;
    }
    const std::string state = "nscdDepositMethods_bed.h5";
    {
        System s = makeSystem(tile(fromSystem(blk, b0), nBig, 1), 0.4);
        s.setContactImpulses(tileContacts(blk, nBig, 1), dt);
        s.settings().maxIterations = 1000;
        for (int k = 0; k < (quick ? 60 : 300); ++k) s.step(dt);
        s.writeHDF5(state);
    }
    std::vector<std::string> restRows;
    for (const Config& c : configs)
        restRows.push_back(restJson(c, state, quick ? 20 : 100, quick ? 30 : 150));
    std::remove(state.c_str());
    std::ofstream o(out);
    o << "{\n    \"what\": \"contact solver methods (System::Settings::Method) on the same problems, one "
         "core, thread CPU time "
      << "(CLOCK_THREAD_CPUTIME_ID); tolerance 1e-6 d_min on the common residual max_k |W_kk (r_k* - r_k)| "
         "dt / d_min, "
      << "at most 1000 sweeps (APGD: iterations) per step; residual histories: residual before the solve and "
         "after each "
      << "sweep-equivalent (NLGS: every contact-count local solves) or iteration (APGD), last entry at the "
         "end of the solve\",\n"
      << "    \"machine\": \"" << machineNote() << "\",\n"
      << "    \"settling_block\": [\n      ";
    for (std::size_t k = 0; k < settleRows.size(); ++k) o << (k ? ",\n      " : "") << settleRows[k];
    o << "\n    ],\n    \"bed_at_rest\": [\n      ";
    for (std::size_t k = 0; k < restRows.size(); ++k) o << (k ? ",\n      " : "") << restRows[k];
    o << "\n    ]\n}\n";
    std::fprintf(stderr, "wrote %s\n", out.c_str());
    return 0;
}
