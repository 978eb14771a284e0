// SPDX-License-Identifier: GPL-3.0-or-later
/*---------------------------------------------------------------------------*\
  nscdFoam: faceReconstructCheck (test application)

Description
    Regression check of the solvers' face-field reconstruction
    (src/vansCoupling/solverTools/faceReconstruct.H) on the case's mesh.
    Why: OpenFOAM v1912's fvc::reconstruct evaluates inv(T) & b on a
    temporary b that GCC 12 -O3 miscompiles (the loop reads components of
    b it has overwritten); on a non-orthogonal mesh the solvers blew up.
    This application is compiled with the solvers' flags, so a return to
    fvc::reconstruct, or a faceReconstruct that again reuses a temporary,
    shows here.

    Reference (independent of the field algebra): for a uniform vector U0
    the face fluxes U0 . S_f reconstruct to U0 exactly on any mesh (the
    formula (sum n S)^-1 . sum n (S . U0) = U0), so the error is round-off.
    For a linear field the reconstruction is compared with the same
    formula evaluated cell by cell with single tensors (no field
    temporaries).  Writes <case>/faceReconstructCheck (a dictionary):
        nonOrthogonality   largest face non-orthogonality [deg]
        uniformError       max |faceReconstruct(U0.S) - U0| / |U0|
        solverError        the same for reconstructFaceField (the solvers'
                           choice: faceReconstruct on a non-orthogonal mesh)
        linearError        max |faceReconstruct - cell-by-cell| / max |U|
        fvcUniformError    max |fvc::reconstruct(U0.S) - U0| / |U0|
                           (information: this build's aliased product)
    Usage: faceReconstructCheck -case <case>
\*---------------------------------------------------------------------------*/

#include "fvCFD.H"
#include "faceReconstruct.H"

using namespace Foam;

namespace
{

//- max over the cells of |a - b|
scalar maxDiff(const volVectorField& a, const vectorField& b)
{
    return gMax(mag(a.primitiveField() - b));
}

//- (sum n S)^-1 . sum n phi per cell, one cell at a time
vectorField cellByCell(const surfaceScalarField& phi)
{
    const fvMesh& mesh = phi.mesh();
    tensorField T(mesh.nCells(), Zero);
    vectorField b(mesh.nCells(), Zero);
    auto add = [&](const label celli, const vector& S, const scalar f)
    {
        const vector n(S/mag(S));
        T[celli] += n*S;
        b[celli] += n*f;
    };
    forAll(mesh.owner(), facei)
    {
        add(mesh.owner()[facei], mesh.Sf()[facei], phi[facei]);
        add(mesh.neighbour()[facei], mesh.Sf()[facei], phi[facei]);
    }
    forAll(mesh.boundary(), patchi)
    {
        const fvPatch& p = mesh.boundary()[patchi];
        forAll(p, i)
        {
            add(p.faceCells()[i], p.Sf()[i], phi.boundaryField()[patchi][i]);
        }
    }
    // 2D: the empty direction has no face; T gets 1 there, as inv() does
    const Vector<label>& D = mesh.solutionD();
    vectorField U(mesh.nCells());
    forAll(U, celli)
    {
        tensor t(T[celli]);
        for (direction c = 0; c < 3; ++c)
        {
            if (D[c] < 0) t(c, c) = 1;
        }
        U[celli] = inv(t) & b[celli];
    }
    return U;
}

} // End anonymous namespace


int main(int argc, char *argv[])
{
    argList::noParallel();
    #include "setRootCase.H"
    #include "createTime.H"
    #include "createMesh.H"

    // a uniform vector, zero along an empty (2D) direction
    vector U0(0.3, -1.7, 0.9);
    vector A(2.0, -0.5, 1.5);
    for (direction c = 0; c < 3; ++c)
    {
        if (mesh.solutionD()[c] < 0)
        {
            U0[c] = 0;
            A[c] = 0;
        }
    }
    const surfaceScalarField phiU("phiU", mesh.Sf() & U0);
    // a linear field U0 + A (x_f . e_y): face values of a non-uniform field
    const surfaceScalarField phiL
    (
        "phiL",
        mesh.Sf()
      & (dimensionedVector("U0", dimLength, U0) + A*mesh.Cf().component(1))
    );

    const scalar nonOrth = maxNonOrthogonality(mesh);
    const bool nonOrthogonal = nonOrth > 1e-3;
    const vectorField uniform(mesh.nCells(), U0);
    const scalar uniformError =
        maxDiff(faceReconstruct(phiU), uniform)/mag(U0);
    const scalar solverError =
        maxDiff(reconstructFaceField(phiU, nonOrthogonal), uniform)/mag(U0);
    const vectorField ref(cellByCell(phiL));
    const scalar linearError =
        maxDiff(faceReconstruct(phiL), ref)/gMax(mag(ref));
    const scalar fvcError =
        maxDiff(fvc::reconstruct(phiU), uniform)/mag(U0);

    OFstream os(runTime.path()/"faceReconstructCheck");
    os.precision(6);
    os  << "nonOrthogonality " << nonOrth << ";" << nl
        << "uniformError " << uniformError << ";" << nl
        << "solverError " << solverError << ";" << nl
        << "linearError " << linearError << ";" << nl
        << "fvcUniformError " << fvcError << ";" << nl;
    Info<< "nonOrthogonality " << nonOrth << " deg: faceReconstruct "
        << uniformError << ", reconstructFaceField " << solverError
        << ", linear field " << linearError << "; fvc::reconstruct "
        << fvcError << nl << "End" << nl << endl;
    return 0;
}


// ************************************************************************* //
