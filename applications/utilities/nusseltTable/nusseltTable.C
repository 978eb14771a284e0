// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam

Application
    nusseltTable

Description
    Tabulates the Nusselt number Nu(eps, Re, Pr) of a run-time selected
    heatTransferModel (src/vansCoupling/heatTransferModels, thesis section
    4.1.2) for a list of Reynolds numbers.  No mesh is needed.

    The model is read from a dictionary, by default the case's
    constant/couplingProperties (entries `heatTransferModel <name>;` and the
    optional `<name>Coeffs { ... }`), or from the file given with -dict.

    Re is the particle Reynolds number rho d |u - v| / mu with the
    INTERSTITIAL slip velocity (the models needing the superficial one form
    eps Re themselves, see heatTransferModel.H).

    Output on stdout (after the banner and the "Selecting" line):
      - plain columns: comment lines starting with '#', then one line
        "Re Nu" per Reynolds number (17 significant digits);
      - with -json, instead, a single line
        {"model": "...", "eps": .., "Pr": .., "Re": [..], "Nu": [..]}.

Usage
    nusseltTable [-case dir] [-dict file] [-eps 0.45] [-Pr 0.71]
                 [-Re '(1 10 100 1000)'] [-json]

    Defaults: eps 0.45, Pr 0.71 (air), Re (0.1 1 10 100 1000 10000).
\*---------------------------------------------------------------------------*/

#include "argList.H"
#include "IFstream.H"
#include "OSspecific.H"
#include "scalarList.H"
#include "heatTransferModel.H"

#include <cstdio>

using namespace Foam;

int main(int argc, char *argv[])
{
    argList::addNote
    (
        "Tabulate the Nusselt number of a heatTransferModel vs Re"
    );
    argList::noParallel();
    argList::noFunctionObjects();
    argList::addOption
    (
        "dict", "file",
        "dictionary holding heatTransferModel"
        " (default: <case>/constant/couplingProperties)"
    );
    argList::addOption("eps", "value", "void fraction in (0, 1] (0.45)");
    argList::addOption("Pr", "value", "Prandtl number > 0 (0.71)");
    argList::addOption
    (
        "Re", "list",
        "interstitial Reynolds numbers >= 0 (default '(0.1 1 10 100 1000 1e4)')"
    );
    argList::addBoolOption("json", "print one JSON line instead of columns");

    #include "setRootCase.H"

    const fileName dictFile
    (
        args.getOrDefault<fileName>
        (
            "dict",
            args.path()/"constant"/"couplingProperties"
        ).expand()
    );
    const scalar eps = args.getOrDefault<scalar>("eps", 0.45);
    const scalar Pr = args.getOrDefault<scalar>("Pr", 0.71);
    scalarList Re({0.1, 1, 10, 100, 1000, 10000});
    args.readListIfPresent<scalar>("Re", Re);

    if (!(eps > 0 && eps <= 1))
    {
        FatalErrorInFunction
            << "-eps " << eps << ": the void fraction must be in (0, 1]"
            << exit(FatalError);
    }
    if (!(Pr > 0))
    {
        FatalErrorInFunction
            << "-Pr " << Pr << ": the Prandtl number must be > 0"
            << exit(FatalError);
    }
    for (const scalar r : Re)
    {
        if (!(r >= 0))
        {
            FatalErrorInFunction
                << "-Re " << Re << ": Reynolds numbers must be >= 0"
                << exit(FatalError);
        }
    }
    if (!isFile(dictFile))
    {
        FatalErrorInFunction
            << "Cannot find the dictionary " << dictFile
            << " (use -dict <file> or a case with constant/couplingProperties)"
            << exit(FatalError);
    }

    IFstream is(dictFile);
    const dictionary dict(is);
    const autoPtr<heatTransferModel> model(heatTransferModel::New(dict));
    const word modelName(dict.get<word>("heatTransferModel"));

    // printf after Info: flush the C++ stream first (same stdout)
    std::cout.flush();
    if (args.found("json"))
    {
        std::printf
        (
            "{\"model\": \"%s\", \"eps\": %.17g, \"Pr\": %.17g, \"Re\": [",
            modelName.c_str(), eps, Pr
        );
        forAll(Re, i)
        {
            std::printf("%s%.17g", i ? ", " : "", Re[i]);
        }
        std::printf("], \"Nu\": [");
        forAll(Re, i)
        {
            std::printf("%s%.17g", i ? ", " : "", model->Nu(eps, Re[i], Pr));
        }
        std::printf("]}\n");
    }
    else
    {
        std::printf
        (
            "# nusseltTable: heatTransferModel %s, eps %.17g, Pr %.17g\n"
            "# Re Nu\n",
            modelName.c_str(), eps, Pr
        );
        for (const scalar r : Re)
        {
            std::printf("%.17g %.17g\n", r, model->Nu(eps, r, Pr));
        }
    }
    std::fflush(stdout);

    return 0;
}
