# SPDX-License-Identifier: GPL-3.0-or-later
"""Pieces of OpenFOAM dictionaries shared by the bench case writers (cfd_dem/openfoam_case.py,
two_fluid/openfoam_case.py): the FoamFile header, writing a dictionary file, the controlDict's
output-format entries and a volFieldValue function object."""
import os

HEADER = """FoamFile
{{
    version     2.0;
    format      ascii;
    class       {cls};
    object      {obj};
}}
"""

# controlDict entries after writeInterval: ASCII fields, 8 digits, no compression.
OUTPUT_FORMAT = """purgeWrite      0;
writeFormat     ascii;
writePrecision  8;
writeCompression off;
timeFormat      general;
timePrecision   8;
runTimeModifiable no;
"""


def write(folder, path, cls, body):
    """Writes FOLDER/PATH: the FoamFile header of class CLS (object: the file's name), then BODY."""
    full = os.path.join(folder, path)
    os.makedirs(os.path.dirname(full), exist_ok=True)
    with open(full, "w") as f:
        f.write(HEADER.format(cls=cls, obj=os.path.basename(path)))
        f.write(body)


def vol_field_value(name, region, operation, field):
    """A volFieldValue function object NAME evaluated every step, not written as fields: OPERATION
    (volAverage, max, ...) of FIELD over REGION (the entries after regionType, e.g. "all" or
    "cellZone;\\n        name            bottomRow")."""
    return f"""    {name}
    {{
        type            volFieldValue;
        libs            ("libfieldFunctionObjects.so");
        writeControl    timeStep;
        writeInterval   1;
        writeFields     false;
        log             false;
        regionType      {region};
        operation       {operation};
        fields          ({field});
    }}
"""
