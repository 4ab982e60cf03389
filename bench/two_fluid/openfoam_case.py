#!/usr/bin/python3
# SPDX-License-Identifier: GPL-3.0-or-later
"""Writes cases/two_fluid/bubbling_bed as an OpenFOAM twoPhaseEulerFoam case (Debian's `openfoam`, v1912).

Based on the v1912 tutorial multiphase/twoPhaseEulerFoam/laminar/fluidisedBed (Debian package
`openfoam-examples`, /usr/share/doc/openfoam-examples/examples/...), changed to grainflow's bed:
the geometry, grains, air, inlet, jet, initial bed and closures are read from the grainflow case
file, so the two stay in step.

- Mesh: blockMesh, the same box and cells (20 x 60, 5 mm), one cell thick in z (depth = the cell
  size along x, as grainflow's 2D depth), `empty` front and back. Three blocks across x (9, 2, 9
  cells) so that the two jet cells have their own inlet patch `jet`.
- Air: rhoConst 1.2 kg/m^3 (grainflow's air is incompressible), mu 1.8e-5 Pa s, laminar.
  Particles: d 0.5 mm, rhoConst 2500 kg/m^3. T = 300 K everywhere (twoPhaseEulerFoam always
  solves both energy equations; here they stay isothermal).
- Inlet: `interstitialInletVelocity` with the superficial 0.25 m/s (patch `inlet`) and 2.5 m/s
  (patch `jet`, x = 45..55 mm), divided by the air fraction at the face as grainflow's
  `superficial: true` inlet; the solids see a no-slip wall there (grainflow: an inlet face is a
  no-slip wall for the solids). Outlet: fixed pressure (prghPressure), air
  pressureInletOutletVelocity, solids inletOutlet (may leave, as grainflow's outlet).
  Side walls: air no-slip, solids slip (grainflow: `solids: free_slip`).
- Initial: alpha.particles 0.55 below y = 0.1 m (setFields), air at 0.5 m/s upwards (grainflow's
  `initial.fluid_velocity`), solids at rest.
- Drag: GidaspowErgunWenYu (= grainflow's `gidaspow`: Ergun below an air fraction of 0.8, Wen-Yu
  above), no swarm correction. No virtual mass, lift, wall lubrication or turbulent dispersion
  (grainflow has none; the tutorial's virtual mass Cvm 0.5 is removed).
- Solids stress: RAS model kineticTheory with `equilibrium on` (the algebraic granular
  temperature), viscosityModel Syamlal, granularPressureModel SyamlalRogersOBrien
  (P = 2 (1 + e) rho_s a^2 g0 Theta, grainflow's `syamlal`), radialModel LunSavage with alphaMax
  0.64 (grainflow's `lun_savage`, packing_limit 0.64), restitution 0.9, frictionalStressModel
  JohnsonJacksonSchaeffer (Johnson-Jackson pressure Fr (a - 0.5)^2 / (0.64 - a)^5 with Fr 0.05
  Pa, Schaeffer viscosity, friction angle 28.5 deg: grainflow's `schaeffer_johnson_jackson`
  defaults), maxNut 0.04 m^2/s (= grainflow's frictional-viscosity cap of 100 Pa s / 2500 kg/m^3).
  What differs (see README.md): OpenFOAM's equilibrium temperature is its own closed form (no
  drag dissipation 3 beta Theta, a Lun-type pressure coefficient rho a (1 + 2 (1 + e) a g0) in
  the balance); its Johnson-Jackson denominator is floored at alphaDeltaMin (`--alpha-delta-min`,
  default 0.05 as in the tutorial) where grainflow's diverges; its cap on the viscosity applies to
  the kinetic part too.
- Numerics: the tutorial's schemes and solvers (vanLeer for alpha, limitedLinear for momentum,
  PIMPLE with 3 outer and 1 pressure corrector, implicit phase pressure, 2 alpha sub-cycles);
  the time step either adjustable (maxCo, maxDeltaT: grainflow's limits, Courant 0.5 and 5e-4 s)
  or fixed (`--fixed-dt`, the tutorial's 2e-4 s).
- Output for the benchmark: `volFieldValue` function objects average p over the bottom and the
  top cell rows (cellZones from topoSet) every step: the pressure drop between the centres of the
  first and the last rows, grainflow's `pressure_drop`; the largest alpha.particles every step;
  the fields every `write` seconds (bed height).

    openfoam_case.py FOLDER [--case cases/two_fluid/bubbling_bed/case.yaml] [--end 0.2]
        [--write 0.01] [--fixed-dt 2e-4] [--max-co 0.5] [--max-dt 5e-4] [--alpha-delta-min 0.05]

Then, in FOLDER: blockMesh; topoSet; setFields; twoPhaseEulerFoam.
"""
import argparse, os, sys

import yaml

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.dirname(HERE))
from openfoam_dict import OUTPUT_FORMAT, vol_field_value, write  # noqa: E402
CASE = os.path.join(ROOT, "cases/two_fluid/bubbling_bed/case.yaml")



def load(case_path=CASE):
    """The figures of the grainflow case that the OpenFOAM case needs (a dict), with a check that
    the case is the bed this script translates (2D, y up, inlet at y_min with a jet, outlet at
    y_max, walls at x)."""
    with open(case_path) as f:
        c = yaml.safe_load(f)["two_fluid"]
    assert c["dimension"] == 2, "2D cases only"
    b = c["boundaries"]
    assert b["y_min"]["type"] == "inlet" and b["y_max"]["type"] == "outlet"
    assert b["x_min"]["type"] == "wall" and b["x_max"]["type"] == "wall"
    s = c["solids"]
    dense = s.get("dense", {})
    jet = b["y_min"].get("jet")
    (x0, y0), (x1, y1) = c["domain"]["min"], c["domain"]["max"]
    nx, ny = c["cells"]
    regions = c.get("initial", {}).get("regions", [])
    assert len(regions) == 1, "one initial region"
    return {
        "lo": (x0, y0), "hi": (x1, y1), "cells": (nx, ny), "depth": (x1 - x0) / nx,
        "gravity": c.get("gravity", [0.0, -9.81]),
        "rho_f": c["fluid"]["density"], "mu_f": c["fluid"]["viscosity"],
        "d": s["grain_diameter"], "rho_s": s["grain_density"], "e": s["restitution"],
        "packing": s.get("packing_limit", 0.64),
        "phi": dense.get("friction_angle", 28.5), "fr": dense.get("fr", 0.05),
        "n": dense.get("exponent_n", 2.0), "p": dense.get("exponent_p", 5.0),
        "a_min_fric": dense.get("min_fraction", 0.5), "a_max_fric": dense.get("max_fraction", 0.64),
        "max_mu": dense.get("max_viscosity", 100.0),
        "u_in": b["y_min"]["velocity"][1], "superficial": b["y_min"].get("superficial", True),
        "jet": (jet["from"], jet["to"], jet["velocity"][1]) if jet else None,
        "p_out": b["y_max"].get("pressure", 0.0),
        "u0": c.get("initial", {}).get("fluid_velocity", [0.0, 0.0])[1],
        "bed_lo": regions[0]["box"]["min"], "bed_hi": regions[0]["box"]["max"],
        "bed_fraction": regions[0]["solids_fraction"],
        "wall_slip": b["x_min"].get("solids", "no_slip") == "free_slip",
        "closures": (s.get("closures"), s.get("radial_distribution"), s.get("temperature"),
                     dense.get("model"), c["drag"]["model"]),
    }


P_REF = 1e5  # OpenFOAM's absolute pressure at the outlet [Pa]; grainflow's is 0 (only p differences are compared)


def make(folder, end, case_path=CASE, write_every=0.01, fixed_dt=None, max_co=0.5,
         max_dt=5e-4, alpha_delta_min=0.05):
    c = load(case_path)
    if c["closures"] != ("syamlal", "lun_savage", "algebraic", "schaeffer_johnson_jackson", "gidaspow"):
        print(f"openfoam_case: warning: the grainflow case uses {c['closures']}; this script "
              "writes Syamlal / LunSavage / equilibrium / JohnsonJacksonSchaeffer / GidaspowErgunWenYu")
    (x0, y0), (x1, y1) = c["lo"], c["hi"]
    nx, ny = c["cells"]
    hx, hy, dz = (x1 - x0) / nx, (y1 - y0) / ny, c["depth"]
    # Blocks across x: [x0, jet.from], [jet.from, jet.to], [jet.to, x1] (cell faces must fall on them).
    if c["jet"]:
        jf, jt, uj = c["jet"]
        xs = [x0, jf, jt, x1]
    else:
        xs = [x0, x1]
    ncx = [round((xs[i + 1] - xs[i]) / hx) for i in range(len(xs) - 1)]
    assert sum(ncx) == nx and all(abs(n * hx - (xs[i + 1] - xs[i])) < 1e-9 for i, n in enumerate(ncx)), \
        "the jet's edges must fall on cell faces"
    nb = len(ncx)

    def v(i, j, k):  # vertex index: i across x (0..nb), j = 0 bottom / 1 top, k = 0 back / 1 front
        return i + (nb + 1) * j + 2 * (nb + 1) * k

    verts = [f"({xs[i]:.9g} {(y0, y1)[j]:.9g} {(0.0, dz)[k]:.9g})"
             for k in range(2) for j in range(2) for i in range(nb + 1)]
    blocks = [f"hex ({v(i,0,0)} {v(i+1,0,0)} {v(i+1,1,0)} {v(i,1,0)} {v(i,0,1)} {v(i+1,0,1)} "
              f"{v(i+1,1,1)} {v(i,1,1)}) ({ncx[i]} {ny} 1) simpleGrading (1 1 1)" for i in range(nb)]

    def bottom(i):
        return f"({v(i+1,0,0)} {v(i+1,0,1)} {v(i,0,1)} {v(i,0,0)})"

    jet_blocks = [1] if c["jet"] else []
    inlet = " ".join(bottom(i) for i in range(nb) if i not in jet_blocks)
    jet = " ".join(bottom(i) for i in jet_blocks)
    outlet = " ".join(f"({v(i,1,0)} {v(i,1,1)} {v(i+1,1,1)} {v(i+1,1,0)})" for i in range(nb))
    walls = f"({v(0,0,0)} {v(0,0,1)} {v(0,1,1)} {v(0,1,0)}) ({v(nb,1,0)} {v(nb,1,1)} {v(nb,0,1)} {v(nb,0,0)})"
    empty = " ".join(f"({v(i,0,0)} {v(i,1,0)} {v(i+1,1,0)} {v(i+1,0,0)}) "
                     f"({v(i,0,1)} {v(i+1,0,1)} {v(i+1,1,1)} {v(i,1,1)})" for i in range(nb))
    jet_patch = f"    patch jet ( {jet} )\n" if jet else ""
    write(folder, "system/blockMeshDict", "dictionary", f"""
scale 1;
vertices ( {' '.join(verts)} );
blocks ( {' '.join(blocks)} );
edges ();
patches
(
    patch inlet ( {inlet} )
{jet_patch}    patch outlet ( {outlet} )
    wall walls ( {walls} )
    empty frontAndBackPlanes ( {empty} )
);
mergePatchPairs ();
""")
    patches = ["inlet", "outlet", "walls"] + (["jet"] if jet else [])

    def bf(entries):
        """boundaryField with the given entries per patch (jet: the inlet's unless given)."""
        e = dict(entries)
        if jet and "jet" not in e:
            e["jet"] = e["inlet"]
        e["frontAndBackPlanes"] = "type empty;"
        return "boundaryField\n{\n" + "".join(f"    {p} {{ {e[p]} }}\n" for p in patches + ["frontAndBackPlanes"]) + "}\n"

    # --- time, output, function objects ------------------------------------------------------
    if fixed_dt:
        stepping = f"deltaT {fixed_dt};\nadjustTimeStep no;\nmaxCo 1;\nmaxDeltaT {fixed_dt};\n"
    else:
        stepping = (f"deltaT {min(max_dt, 1e-4)};\nadjustTimeStep yes;\nmaxCo {max_co};\n"
                    f"maxDeltaT {max_dt};\n")
    def row(name):  # the volume average of p over a cell zone
        return vol_field_value(name, f"cellZone;\n        name            {name}", "volAverage", "p")

    write(folder, "system/controlDict", "dictionary", f"""
application     twoPhaseEulerFoam;
startFrom       startTime;
startTime       0;
stopAt          endTime;
endTime         {end};
{stepping}writeControl    adjustableRunTime;
writeInterval   {write_every};
{OUTPUT_FORMAT}functions
{{
{row("bottomRow")}{row("topRow")}{vol_field_value("alphaMax", "all", "max", "alpha.particles")}}}
""")
    write(folder, "system/topoSetDict", "dictionary", f"""
actions
(
    {{ name bottomRow; type cellZoneSet; action new; source boxToCell;
       box ({x0 - 1} {y0 - 1e-9} -1) ({x1 + 1} {y0 + hy} 1); }}
    {{ name topRow; type cellZoneSet; action new; source boxToCell;
       box ({x0 - 1} {y1 - hy} -1) ({x1 + 1} {y1 + 1e-9} 1); }}
);
""")
    (bx0, by0), (bx1, by1) = c["bed_lo"], c["bed_hi"]
    a0 = c["bed_fraction"]
    write(folder, "system/setFieldsDict", "dictionary", f"""
defaultFieldValues
(
    volScalarFieldValue alpha.air 1
    volScalarFieldValue alpha.particles 0
);
regions
(
    boxToCell
    {{
        box ({bx0} {by0} -1) ({bx1} {by1} 1);
        fieldValues
        (
            volScalarFieldValue alpha.air {1 - a0:.12g}
            volScalarFieldValue alpha.particles {a0:.12g}
        );
    }}
);
""")
    # --- schemes and solvers: the tutorial's ---------------------------------------------------
    write(folder, "system/fvSchemes", "dictionary", """
ddtSchemes { default Euler; }
gradSchemes { default Gauss linear; }
divSchemes
{
    default                         none;
    "div\\(phi,alpha.*\\)"            Gauss vanLeer;
    "div\\(phir,alpha.*\\)"           Gauss vanLeer;
    "div\\(alphaRhoPhi.*,U.*\\)"      Gauss limitedLinearV 1;
    "div\\(phi.*,U.*\\)"              Gauss limitedLinearV 1;
    "div\\(alphaRhoPhi.*,(h|e).*\\)"  Gauss limitedLinear 1;
    "div\\(alphaRhoPhi.*,K.*\\)"      Gauss limitedLinear 1;
    "div\\(alphaPhi.*,p\\)"           Gauss limitedLinear 1;
    div(alphaRhoPhi.particles,Theta.particles) Gauss limitedLinear 1;
    div((((alpha.air*thermo:rho.air)*nuEff.air)*dev2(T(grad(U.air))))) Gauss linear;
    div((((thermo:rho.particles*nut.particles)*dev2(T(grad(U.particles))))+(((thermo:rho.particles*lambda.particles)*div(phi.particles))*I)))  Gauss linear;
}
laplacianSchemes { default Gauss linear uncorrected; bounded Gauss linear uncorrected; }
interpolationSchemes { default linear; }
snGradSchemes { default uncorrected; bounded uncorrected; }
""")
    write(folder, "system/fvSolution", "dictionary", """
solvers
{
    "alpha.*"
    {
        nAlphaCorr      1;
        nAlphaSubCycles 2;
        smoothLimiter   0.1;
        implicitPhasePressure yes;
        solver          smoothSolver;
        smoother        symGaussSeidel;
        tolerance       1e-9;
        relTol          0;
        minIter         1;
    }
    p_rgh { solver GAMG; smoother DIC; tolerance 1e-8; relTol 0; }
    p_rghFinal { $p_rgh; relTol 0; }
    "U.*" { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-5; relTol 0; minIter 1; }
    "(h|e).*" { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-6; relTol 0; minIter 1; }
    "Theta.*" { solver smoothSolver; smoother symGaussSeidel; tolerance 1e-6; relTol 0; minIter 1; }
}
PIMPLE
{
    nOuterCorrectors    3;
    nCorrectors         1;
    nNonOrthogonalCorrectors 0;
}
relaxationFactors { equations { ".*" 1; } }
""")
    # --- physics -------------------------------------------------------------------------------
    gx, gy = c["gravity"]
    write(folder, "constant/g", "uniformDimensionedVectorField",
          f"dimensions [0 1 -2 0 0 0 0];\nvalue ({gx} {gy} 0);\n")
    write(folder, "constant/phaseProperties", "dictionary", f"""
phases (particles air);
particles
{{
    diameterModel constant;
    constantCoeffs {{ d {c['d']}; }}
    alphaMax        {c['packing']};
    residualAlpha   1e-6;
}}
air
{{
    diameterModel constant;
    constantCoeffs {{ d 1; }}
    residualAlpha   0;
}}
blending {{ default {{ type none; continuousPhase air; }} }}
sigma ( (particles and air) 0 );
aspectRatio ();
drag
(
    (particles in air)
    {{
        type            GidaspowErgunWenYu;
        residualRe      1e-3;
        swarmCorrection {{ type none; }}
    }}
);
virtualMass ();
heatTransfer
(
    (particles in air)
    {{
        type            RanzMarshall;
        residualAlpha   1e-3;
    }}
);
lift ();
wallLubrication ();
turbulentDispersion ();
pMin            10000;
""")
    thermo = lambda rho, mu, cp, mw: f"""
thermoType
{{
    type            heRhoThermo;
    mixture         pureMixture;
    transport       const;
    thermo          hConst;
    equationOfState rhoConst;
    specie          specie;
    energy          sensibleInternalEnergy;
}}
mixture
{{
    specie {{ molWeight {mw}; }}
    equationOfState {{ rho {rho}; }}
    thermodynamics {{ Cp {cp}; Hf 0; }}
    transport {{ mu {mu}; Pr {0.7 if mu > 0 else 1}; }}
}}
"""
    write(folder, "constant/thermophysicalProperties.air", "dictionary",
          thermo(c["rho_f"], c["mu_f"], 1007, 28.9))
    write(folder, "constant/thermophysicalProperties.particles", "dictionary",
          thermo(c["rho_s"], 0, 6000, 100))
    write(folder, "constant/turbulenceProperties.air", "dictionary", "simulationType laminar;\n")
    assert abs(c["a_max_fric"] - c["packing"]) < 1e-12, "OpenFOAM has one alphaMax for g0 and friction"
    write(folder, "constant/turbulenceProperties.particles", "dictionary", f"""
simulationType  RAS;
RAS
{{
    RASModel        kineticTheory;
    turbulence      on;
    printCoeffs     on;
    kineticTheoryCoeffs
    {{
        equilibrium             on;
        e                       {c['e']};
        alphaMax                {c['packing']};
        alphaMinFriction        {c['a_min_fric']};
        residualAlpha           1e-4;
        maxNut                  {c['max_mu'] / c['rho_s']:.9g};
        viscosityModel          Syamlal;
        conductivityModel       Syamlal;
        granularPressureModel   SyamlalRogersOBrien;
        frictionalStressModel   JohnsonJacksonSchaeffer;
        radialModel             LunSavage;
        JohnsonJacksonSchaefferCoeffs
        {{
            Fr                      {c['fr']};
            eta                     {c['n']};
            p                       {c['p']};
            phi                     {c['phi']};
            alphaDeltaMin           {alpha_delta_min};
        }}
    }}
}}
""")
    # --- initial and boundary fields -------------------------------------------------------------
    assert c["superficial"], "interstitialInletVelocity takes the superficial velocity"
    zero_grad = "type zeroGradient;"
    fields = {
        "U.air": ("volVectorField", "[0 1 -1 0 0 0 0]", f"uniform (0 {c['u0']} 0)", {
            "inlet": f"type interstitialInletVelocity; inletVelocity uniform (0 {c['u_in']} 0); "
                     f"alpha alpha.air; value uniform (0 {c['u_in']} 0);",
            **({"jet": f"type interstitialInletVelocity; inletVelocity uniform (0 {uj} 0); "
                       f"alpha alpha.air; value uniform (0 {uj} 0);"} if jet else {}),
            "outlet": "type pressureInletOutletVelocity; phi phi.air; value uniform (0 0 0);",
            "walls": "type noSlip;"}),
        "U.particles": ("volVectorField", "[0 1 -1 0 0 0 0]", "uniform (0 0 0)", {
            "inlet": "type fixedValue; value uniform (0 0 0);",
            "outlet": "type inletOutlet; phi phi.particles; inletValue uniform (0 0 0); value uniform (0 0 0);",
            "walls": "type slip;" if c["wall_slip"] else "type fixedValue; value uniform (0 0 0);"}),
        "alpha.air": ("volScalarField", "[0 0 0 0 0 0 0]", "uniform 1", {
            "inlet": zero_grad, "outlet": zero_grad, "walls": zero_grad}),
        "alpha.particles": ("volScalarField", "[0 0 0 0 0 0 0]", "uniform 0", {
            "inlet": zero_grad, "outlet": zero_grad, "walls": zero_grad}),
        "p": ("volScalarField", "[1 -1 -2 0 0 0 0]", f"uniform {P_REF}", {
            "inlet": f"type calculated; value uniform {P_REF};",
            "outlet": f"type calculated; value uniform {P_REF};",
            "walls": f"type calculated; value uniform {P_REF};"}),
        "p_rgh": ("volScalarField", "[1 -1 -2 0 0 0 0]", f"uniform {P_REF}", {
            "inlet": f"type fixedFluxPressure; value uniform {P_REF};",
            "outlet": f"type prghPressure; p uniform {P_REF + c['p_out']}; value uniform {P_REF};",
            "walls": f"type fixedFluxPressure; value uniform {P_REF};"}),
        "T.air": ("volScalarField", "[0 0 0 1 0 0 0]", "uniform 300", {
            "inlet": "type fixedValue; value uniform 300;",
            "outlet": "type inletOutlet; phi phi.air; inletValue uniform 300; value uniform 300;",
            "walls": zero_grad}),
        "T.particles": ("volScalarField", "[0 0 0 1 0 0 0]", "uniform 300", {
            "inlet": zero_grad,
            "outlet": "type inletOutlet; phi phi.particles; inletValue uniform 300; value uniform 300;",
            "walls": zero_grad}),
        "Theta.particles": ("volScalarField", "[0 2 -2 0 0 0 0]", "uniform 0", {
            "inlet": zero_grad, "outlet": zero_grad, "walls": zero_grad}),
        "nut.particles": ("volScalarField", "[0 2 -1 0 0 0 0]", "uniform 0", {
            "inlet": "type calculated; value uniform 0;", "outlet": "type calculated; value uniform 0;",
            "walls": "type calculated; value uniform 0;"}),
        "alphat.particles": ("volScalarField", "[1 -1 -1 0 0 0 0]", "uniform 0", {
            "inlet": "type calculated; value uniform 0;", "outlet": "type calculated; value uniform 0;",
            "walls": "type calculated; value uniform 0;"}),
    }
    for name, (cls, dims, internal, entries) in fields.items():
        write(folder, f"0/{name}", cls,
              f"\ndimensions {dims};\ninternalField {internal};\n" + bf(entries))


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("folder")
    ap.add_argument("--case", default=CASE, help="the grainflow case file")
    ap.add_argument("--end", type=float, default=0.2, help="simulated time, s")
    ap.add_argument("--write", type=float, default=0.01, help="field output interval, s")
    ap.add_argument("--fixed-dt", type=float, default=None, help="fixed time step, s (default: adjustable)")
    ap.add_argument("--max-co", type=float, default=0.5, help="Courant limit of the adjustable step")
    ap.add_argument("--max-dt", type=float, default=5e-4, help="largest adjustable step, s")
    ap.add_argument("--alpha-delta-min", type=float, default=0.05,
                    help="floor of (alphaMax - a) in the Johnson-Jackson pressure")
    a = ap.parse_args()
    make(a.folder, a.end, a.case, a.write, a.fixed_dt, a.max_co, a.max_dt, a.alpha_delta_min)
