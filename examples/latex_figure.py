"""Render the LaTeX observability matrix of planar SLAM to docs/images/latex-slam2d.png (the docs' image).

    python examples/latex_figure.py            # needs pdflatex and pypdfium2 (pip install -e '.[test]')

The document is what `observability latex slam2d` writes; its first page is
compiled, rendered at 150 dpi and cropped to the ink.
"""

import io
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pypdfium2

from observability import analyze, models
from observability.report.files import write_bytes
from observability.report.latex import latex_document

OUT = Path(__file__).resolve().parents[1] / "docs" / "images" / "latex-slam2d.png"


def main() -> int:
    engine = shutil.which("pdflatex")
    if engine is None:
        print("latex_figure.py: pdflatex not found", file=sys.stderr)
        return 2
    system = models.build("slam2d")
    with tempfile.TemporaryDirectory() as tmp:
        (Path(tmp) / "m.tex").write_text(latex_document(system, analyze(system, seed=1)))
        subprocess.run([engine, "-interaction=nonstopmode", "-halt-on-error", "m.tex"], cwd=tmp, check=True,
                       capture_output=True)
        page = pypdfium2.PdfDocument(str(Path(tmp) / "m.pdf"))[0].render(scale=150 / 72).to_pil()
    ink = np.argwhere(np.asarray(page.convert("L")) < 200)
    (top, left), (bottom, right) = ink.min(axis=0), ink.max(axis=0)
    cropped = page.crop((max(left - 20, 0), max(top - 20, 0), right + 20, bottom + 20))
    buffer = io.BytesIO()
    cropped.save(buffer, format="PNG", optimize=True)
    write_bytes(OUT, buffer.getvalue())
    print(f"wrote {OUT} ({cropped.size[0]}x{cropped.size[1]})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
