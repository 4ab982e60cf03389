#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes cases/cfd_dem/fluidized_bed as an OpenFOAM DPMFoam case (Debian's `openfoam`, v1912).

The same box (50.4 x 12.6 x 189 mm, 8 x 2 x 30 cells), the same 3024 glass beads (d = 2 mm,
rho 2500, E = 1e7, nu = 0.3) on the same cubic lattice (spacing 2.1 mm), air (rho 1.2, mu 1.8e-5)
entering the floor at a superficial velocity of 2.5 m/s, a fixed pressure at the top, no-slip side
walls, gravity, the same fluid step (2.5e-4 s). Drag: OpenFOAM's ErgunWenYuDrag, the law grainflow
calls `gidaspow` (the benchmark runs grainflow with it). Contacts: OpenFOAM's pair and wall
spring-slider-dashpot with b = 1.5 (Hertzian), friction 0.3, Tsuji's damping alpha = 0.2
(restitution ~0.9, as in the grainflow case), the collision sub-step a contact duration / 15
(grainflow's DEM step is 1/15.5 of the Hertz contact time at the case's impact speed). What
differs: OpenFOAM's PIMPLE/PISO (2 pressure corrections) and its collision sub-cycling pick
their own iterations and sub-steps, and its particle-fluid coupling is cell-based.

The grains see the fluid velocity of their cell (`U.air cell`), not OpenFOAM's `cellPoint`
interpolation: the box is 2 cells deep between no-slip walls, so every cell touches a wall and
`cellPoint` blends the walls' zero velocity into what every grain sees; with it the bed did not
fluidise at 1.75 U_mf (2026-11-24: mean height 21 mm at 0.1 s, alpha.air unchanged), with the
cell value it lifts within 0.02 s as grainflow's does (grainflow interpolates the cell-centred
field trilinearly and holds the wall cells' values up to the walls: no wall value blended in).

    openfoam_case.py FOLDER [--end 0.1]
"""
import argparse, os, sys

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
from openfoam_dict import OUTPUT_FORMAT, write  # noqa: E402


LX, LY, LZ = 0.0504, 0.0126, 0.189
CELLS = (8, 2, 30)
SPACING, NX, NY, NZ = 0.0021, 24, 6, 21
DT_FLUID = 2.5e-4


def make(folder, end):
    write(folder, "system/controlDict", "dictionary", f"""
application     DPMFoam;
startFrom       startTime;
startTime       0;
stopAt          endTime;
endTime         {end};
deltaT          {DT_FLUID};
writeControl    runTime;
writeInterval   {end};
{OUTPUT_FORMAT}""")
    write(folder, "system/blockMeshDict", "dictionary", f"""
vertices
(
    (0 0 0) ({LX} 0 0) ({LX} {LY} 0) (0 {LY} 0)
    (0 0 {LZ}) ({LX} 0 {LZ}) ({LX} {LY} {LZ}) (0 {LY} {LZ})
);
blocks ( hex (0 1 2 3 4 5 6 7) ({CELLS[0]} {CELLS[1]} {CELLS[2]}) simpleGrading (1 1 1) );
edges ();
boundary
(
    bottom {{ type wall; faces ((0 3 2 1)); }}
    top {{ type wall; faces ((4 5 6 7)); }}
    walls {{ type wall; faces ((0 1 5 4) (2 3 7 6) (1 2 6 5) (3 0 4 7)); }}
);
""")
    write(folder, "system/fvSchemes", "dictionary", """
ddtSchemes { default Euler; }
gradSchemes { default Gauss linear; }
divSchemes
{
    default none;
    div(alphaPhi.air,U.air) Gauss linearUpwindV unlimited;
    div(((alpha.air*nuEff.air)*dev2(T(grad(U.air))))) Gauss linear;
}
laplacianSchemes { default Gauss linear corrected; }
interpolationSchemes { default linear; }
snGradSchemes { default corrected; }
""")
    write(folder, "system/fvSolution", "dictionary", """
solvers
{
    "(p|kinematicCloud:theta)" { solver GAMG; smoother GaussSeidel; tolerance 1e-6; relTol 0.01; }
    "(p|kinematicCloud:theta)Final" { solver GAMG; smoother GaussSeidel; tolerance 1e-6; relTol 0; }
    U.air { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-5; relTol 0.1; }
    U.airFinal { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-5; relTol 0; }
}
PIMPLE
{
    nOuterCorrectors 1;
    nCorrectors 2;
    momentumPredictor yes;
    nNonOrthogonalCorrectors 0;
    pRefCell 0;
    pRefValue 0;
}
relaxationFactors {}
""")
    write(folder, "constant/g", "uniformDimensionedVectorField",
          "dimensions [0 1 -2 0 0 0 0];\nvalue (0 0 -9.81);\n")
    write(folder, "constant/transportProperties", "dictionary",
          f"continuousPhase air;\nrho.air 1.2;\ntransportModel Newtonian;\nnu {1.8e-5 / 1.2};\n")
    write(folder, "constant/turbulenceProperties.air", "dictionary", "simulationType laminar;\n")
    positions = [((i + 0.5) * SPACING, (j + 0.5) * SPACING, (k + 0.5) * SPACING)
                 for k in range(NZ) for j in range(NY) for i in range(NX)]
    write(folder, "constant/kinematicCloudPositions", "vectorField",
          "\n(\n" + "".join(f"({x:.6g} {y:.6g} {z:.6g})\n" for x, y, z in positions) + ")\n")
    rebound = "{ type rebound; e 0.9; mu 0.3; }"
    write(folder, "constant/kinematicCloudProperties", "dictionary", f"""
solution
{{
    active true;
    coupled true;
    transient yes;
    cellValueSourceCorrection off;
    interpolationSchemes {{ rho.air cell; U.air cell; mu.air cell; }}
    integrationSchemes {{ U Euler; }}
    sourceTerms {{ schemes {{ U semiImplicit 1; }} }}
}}
constantProperties
{{
    parcelTypeId 1;
    rhoMin 1e-15;
    minParcelMass 1e-15;
    rho0 2500;
    youngsModulus 1e7;
    poissonsRatio 0.3;
    constantVolume false;
    alphaMax 0.99;
}}
subModels
{{
    particleForces
    {{
        ErgunWenYuDrag {{ alphac alpha.air; }}
        gravity;
    }}
    injectionModels
    {{
        lattice
        {{
            type manualInjection;
            massTotal 0;
            parcelBasisType fixed;
            nParticle 1;
            SOI 0;
            positionsFile "kinematicCloudPositions";
            U0 (0 0 0);
            sizeDistribution {{ type fixedValue; fixedValueDistribution {{ value 0.002; }} }}
        }}
    }}
    dispersionModel none;
    patchInteractionModel localInteraction;
    localInteractionCoeffs
    {{
        patches ( bottom {rebound} top {rebound} walls {rebound} );
    }}
    heatTransferModel none;
    surfaceFilmModel none;
    collisionModel pairCollision;
    pairCollisionCoeffs
    {{
        maxInteractionDistance 0.002;
        writeReferredParticleCloud no;
        pairModel pairSpringSliderDashpot;
        pairSpringSliderDashpotCoeffs
        {{
            useEquivalentSize no;
            alpha 0.2;
            b 1.5;
            mu 0.3;
            cohesionEnergyDensity 0;
            collisionResolutionSteps 15;
        }};
        wallModel wallSpringSliderDashpot;
        wallSpringSliderDashpotCoeffs
        {{
            useEquivalentSize no;
            collisionResolutionSteps 15;
            youngsModulus 1e7;
            poissonsRatio 0.3;
            alpha 0.2;
            b 1.5;
            mu 0.3;
            cohesionEnergyDensity 0;
        }};
        U U.air;
    }}
    stochasticCollisionModel none;
    radiation off;
}}
cloudFunctions {{}}
""")
    write(folder, "0/U.air", "volVectorField", """
dimensions [0 1 -1 0 0 0 0];
internalField uniform (0 0 0);
boundaryField
{
    walls { type noSlip; }
    top
    {
        type pressureInletOutletVelocity;
        phi phi.air;
        inletValue uniform (0 0 0);
        value uniform (0 0 0);
    }
    bottom
    {
        type interstitialInletVelocity;
        inletVelocity uniform (0 0 2.5);
        value uniform (0 0 2.5);
        phi phi.air;
        alpha alpha.air;
    }
}
""")
    write(folder, "0/p", "volScalarField", """
dimensions [0 2 -2 0 0 0 0];
internalField uniform 0;
boundaryField
{
    walls { type fixedFluxPressure; value $internalField; }
    bottom { type fixedFluxPressure; value $internalField; }
    top { type fixedValue; value $internalField; }
}
""")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("folder")
    ap.add_argument("--end", type=float, default=0.1, help="simulated time, s")
    a = ap.parse_args()
    make(a.folder, a.end)
