"""What the knot figures share: saving a figure as PNG and as PDF beside it."""


def save_png_and_pdf(fig, out, dpi=110):
    """Writes @p fig to @p out (a .png path) and to the .pdf beside it, and says so."""
    fig.tight_layout()
    fig.savefig(out, dpi=dpi)
    fig.savefig(out.with_suffix(".pdf"))
    print(f"wrote {out} and {out.with_suffix('.pdf')}")
