// nscdFoam: tutorials/vansInterFoam/lituyaBay
// 2D cross-section of Gilbert Inlet, Lituya Bay (thesis section 5.3, Fig. 5.9):
// water depth H, shore-to-shore length L at the still-water level, both shores
// at 45 degrees, atmosphere on top at y = Ytop.  x = 0 is the initial left
// shoreline, y = 0 the still-water level.  Meshed as a one-cell-thick slab
// (extrusion by dz in z, recombined: hexahedra + a few prisms) for gmshToFoam:
//   gmsh -3 lituyaBay.geo -setnumber hFine 4 ... -format msh2 -o lituyaBay.msh
// Cell size hFine in the water, the run-up zone (y < yFine), a band of
// width bandFine along the left slope (the slide path) and, if bandRight > 0,
// a band of that width along the whole right shore (the run-up shore as a
// thin layer can climb it); hCoarse elsewhere.
DefineConstant[ H = 122, L = 1342, Ytop = 1050, dz = 1,
                hFine = 4, hCoarse = 40, yFine = 250, bandFine = 150,
                bandRight = 0 ];

Point(1) = {-Ytop, Ytop, 0, hCoarse};      // top of the left shore
Point(2) = {H, -H, 0, hFine};              // toe of the left shore
Point(3) = {L - H, -H, 0, hFine};          // toe of the right shore
Point(4) = {L + Ytop, Ytop, 0, hCoarse};   // top of the right shore
Line(1) = {1, 2};   // left shore (slide plane), 45 degrees
Line(2) = {2, 3};   // bay bottom
Line(3) = {3, 4};   // right shore (run-up), 45 degrees
Line(4) = {4, 1};   // atmosphere
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

// size field: fine below yFine and within bandFine of the left slope x + y = 0
Field[1] = MathEval;
Field[1].F = Sprintf("Min(%g + (%g - %g)*Min(1, Max(0, (y - %g)/%g)), %g + (%g - %g)*Min(1, Max(0, ((x + y)/Sqrt(2) - %g)/%g)))",
    hFine, hCoarse, hFine, yFine, 4*hCoarse, hFine, hCoarse, hFine, bandFine, 4*hCoarse);
// and within bandRight of the right shore y - x + L = 0
Field[2] = MathEval;
Field[2].F = Sprintf("%g + (%g - %g)*Min(1, Max(0, ((y - x + %g)/Sqrt(2) - %g)/%g))",
    hFine, hCoarse, hFine, L, bandRight, 4*hCoarse);
Field[3] = Min;
Field[3].FieldsList = {1, 2};
Background Field = (bandRight > 0) ? 3 : 1;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.CharacteristicLengthExtendFromBoundary = 0;
Mesh.Algorithm = 6;          // frontal-Delaunay, recombined into quads (8 crashes gmsh 4.8.4 here)
Mesh.RecombineAll = 1;
Mesh.RecombinationAlgorithm = 1;

out[] = Extrude {0, 0, dz} { Surface{1}; Layers{1}; Recombine; };
// out[0]: top surface, out[1]: volume, out[2..5]: sides of lines 1..4
Physical Surface("frontAndBack") = {1, out[0]};
Physical Surface("leftShore") = {out[2]};
Physical Surface("bottom") = {out[3]};
Physical Surface("rightShore") = {out[4]};
Physical Surface("atmosphere") = {out[5]};
Physical Volume("fluid") = {out[1]};
