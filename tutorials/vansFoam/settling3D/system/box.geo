// nscdFoam: tutorials/vansFoam/settling3D - the box of blockMeshDict meshed
// by gmsh in tetrahedra (Allrun with MESH=gmsh or MESH=polyhedral):
// 4 x 8 x 4 cm, tets of at most 4 mm, one physical surface "walls".
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.04, 0.08, 0.04};
Mesh.CharacteristicLengthMax = 0.004;
Physical Surface("walls") = {1, 2, 3, 4, 5, 6};
Physical Volume("water") = {1};
