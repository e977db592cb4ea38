"""Reading the papers' printed cells (paper_figures.py) as numbers."""


def parse_row(text, resolutions, unit):
    """{resolution: value} from a printed row; `unit` converts one printed cell."""
    cells = text.split()
    assert len(cells) == len(resolutions), text
    return {r: unit(c) for r, c in zip(resolutions, cells) if c != "-"}


def seconds(cell):
    return float(cell[:-2]) / 1000 if cell.endswith("ms") else float(cell.rstrip("s"))


def decimal_bytes(cell):
    for suffix, scale in (("KB", 1e3), ("MB", 1e6), ("GB", 1e9)):
        if cell.endswith(suffix):
            return float(cell[:-2]) * scale
    return float(cell) * 1e6  # Kämpe's cells are MB


def paper_mib(text, resolutions):
    """A printed row of MB (the MH papers': read as 2^20 bytes, i.e. MiB) as {resolution: MiB}."""
    return parse_row(text, resolutions, float)
