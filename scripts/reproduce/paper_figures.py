"""The papers' published figures, as printed, and nothing else: the renderers (cpvs_tables.py,
mh_tables.py) read them and printed.py turns a printed row into numbers.

Kept as Python literals rather than JSON or TOML: each figure keeps its citation and the
reading of its units (and the papers' misprints) in a comment beside it, and the keys are
resolutions and tuples, which JSON and TOML could hold only as strings behind a conversion layer.
Units: the CPVS papers' "KB"/"MB" are 10^3/10^6 bytes (Sintorn's percentages of 2·R² bytes give
Kämpe's "old" MB only in decimal MB); the MH papers' "MB" are 2^20 bytes (see their section).
A row is a string of cells, one per resolution of its table, "-" where the paper has none.
"""

K = 1024

# --- Sintorn et al. 2014 and Kämpe et al. 2015 (CPVS) ------------------------------------------

# Sintorn et al. 2014, Fig. 9 "Compression results": per scene and build, the size and the size
# as % of a 16-bit shadow map, at 1K² 4K² 16K² 32K² 128K² 256K² ("-": not built).
SINTORN_FIG9_RESOLUTIONS = [1 * K, 4 * K, 16 * K, 32 * K, 128 * K, 256 * K]
SINTORN_FIG9 = {
    "ClosedCity closed": ("202KB 1MB 6MB 13MB 50MB 100MB", "9.61 3.53 1.16 0.60 0.14 0.07"),
    "ClosedCity not closed": ("489KB 4MB 36MB 96MB 639MB 1638MB",
                              "23.32 12.41 6.69 4.48 1.86 1.19"),
    "FractalLandscape closed": ("164KB 759KB 3MB 7MB 29MB 61MB", "7.81 2.26 0.62 0.33 0.09 0.04"),
    "FractalLandscape not closed": ("490KB 5MB 50MB 146MB 1155MB -",
                                    "23.37 14.34 9.29 6.81 3.36 -"),
    "Necropolis not closed": ("539KB 5MB 37MB 100MB 657MB -", "25.72 13.66 6.94 4.66 1.91 -"),
    "Necropolis static geometry": ("444KB 3MB 14MB 31MB 144MB -", "21.19 8.43 2.69 1.46 0.42 -"),
    # EpicCitadel not closed (585KB … 727MB) has no stand-in among our scenes.
}

# Kämpe et al. 2015 reports 4K³ … 256K³ (Tables 1, 2, 4) and 4K³ 16K³ 64K³ 256K³ (Table 3).
KAMPE_RESOLUTIONS = [4 * K, 8 * K, 16 * K, 32 * K, 64 * K, 128 * K, 256 * K]
KAMPE_TABLE3_RESOLUTIONS = [4 * K, 16 * K, 64 * K, 256 * K]

# Kämpe Table 1, ClosedCity: (total, insert/merge) without and with culling of identical nodes.
# The row labels are lost in the text; the culled rows are Table 4's ClosedCity times, and the
# insert/merge saved by culling is the same in absolute terms open and closed (Kämpe §5.1).
KAMPE_TABLE1 = {
    ("non-closed", "off"): ("434ms 1.7s 6.5s 24.1s 92.7s 357.9s 1398.8s",
                            "417ms 1.7s 6.4s 23.5s 90.3s 348.6s 1362.4s"),
    ("closed", "off"): ("235ms 695ms 2.5s 9.1s 35.8s 139.5s 550.5s",
                        "146ms 580ms 2.3s 8.4s 33.2s 130.1s 515.2s"),
    ("non-closed", "on"): ("300ms 1.2s 4.5s 16.3s 61.5s 235.4s 906.4s",
                           "283ms 1.2s 4.4s 15.7s 59.2s 226.1s 870.1s"),
    ("closed", "on"): ("113ms 185ms 377ms 1.1s 3.3s 10.9s 38.1s",
                       "25ms 72ms 151ms 347ms 763ms 1.6s 3.3s"),
}

# Kämpe Table 2, closed object optimisation: (new MB, old MB, ratio old/new).
KAMPE_TABLE2 = {
    "ClosedCity": ("0.83 1.89 3.96 7.70 14.28 26.15 48.04",
                   "1.18 2.82 6.25 12.87 25.43 49.72 100.05",
                   "1.43 1.49 1.58 1.67 1.78 1.90 2.08"),
    "FractalLandscape": ("0.44 0.84 1.60 3.05 5.76 10.85 20.35",
                         "0.76 1.59 3.34 6.98 14.36 29.30 60.99",
                         "1.72 1.90 2.08 2.29 2.49 2.70 3.00"),
}

# Kämpe Table 3, ClosedCity, at 4K³ 16K³ 64K³ 256K³: the total, then each step.
KAMPE_TABLE3 = {
    "non-closed": {
        "total": "300ms 4.5s 61.5s 906.4s",
        "enter depth map": "4ms 20ms 291ms 4.5s",
        "visibility masks": "2ms 29ms 482ms 7.8s",
        "min-max": "1ms 1ms 7ms 119ms",
        "transfer": "7ms 90ms 1.4s 22.6s",
        "insert nodes": "107ms 1.7s 22.1s 339.8s",
        "merge nodes": "176ms 2.7s 37.2s 530.4s",
    },
    "closed": {
        "total": "113ms 377ms 3.3s 38.1s",
        "enter depth map": "5ms 19ms 271ms 4.4s",
        "exit depth map": "78ms 176ms 1.8s 23.0s",
        "visibility masks": "1ms 12ms 181ms 2.9s",
        "min-max": "1ms 1ms 7ms 111ms",
        "transfer": "2ms 16ms 245ms 3.9s",
        "insert nodes": "10ms 63ms 312ms 1.4s",
        "merge nodes": "15ms 88ms 451ms 2.0s",
    },
}

# Kämpe Table 4, total construction times. The last row is Sintorn 2014's own build-time table
# (§7), which is of FractalLandscape, closed; Kämpe prints its 18.0s under 8K³ and nothing under
# 16K³, where Sintorn's table has it (Sintorn built no 8K³), so it stands at 16K³ here.
KAMPE_TABLE4 = {
    "Necropolis non-closed": "209ms 720ms 2.6s 9.6s 34.5s 126.6s 470.4s",
    "ClosedCity non-closed": "300ms 1.2s 4.5s 16.3s 61.5s 235.4s 906.4s",
    "ClosedCity closed": "113ms 185ms 377ms 1.1s 3.3s 10.9s 38.1s",
    "FractalLandscape non-closed": "264ms 1.0s 4.0s 15.2s 57.6s 220.7s 874.2s",
    "FractalLandscape closed": "56ms 91ms 192ms 570ms 2.0s 7.1s 25.3s",
    "Sintorn 2014 closed (FractalLandscape)": "2.0s - 18.0s 68.0s 256.0s 1055.0s 5520.0s",
}

# Sintorn 2014 §7 "Evaluation performance": GPU shading time per frame of the fly-throughs, at
# worst 2.5× from 1 tap to 9×9 and 4.5× to 17×17.
SINTORN_WORST_RATIO = {9: 2.5, 17: 4.5}

# Triangles of the papers' scenes (Sintorn 2014 §7; Kämpe 2015 uses the same scenes and light).
PAPER_TRIANGLES = {"ClosedCity": "613k", "FractalLandscape": "2.1M", "Necropolis": "2.1M",
                   # Scandolo et al. 2016 §4; Scandolo & Eisemann 2021 gives no counts
                   "CLOSED CITY": "613k", "CITYSCAPE": "11k", "VILLA": "89k", "SHIP": "810k"}


# --- Scandolo et al. 2016 (MMH) and Scandolo & Eisemann 2021 (DAG-MH) -------------------------
# Their "MB" is read as 2^20 bytes (MiB): the 2021 paper's Uncompressed row is 4·R² bytes / 2^20
# (64 at 4K², 1048576 at 512K²), and its Table 3 treelet sizes at 16K² are 12-byte treelets
# (§3.2) / 2^20 (21595 × 12 B = 0.247, 14666 × 44 B = 0.615); the 2016 paper, by the same
# authors, does not say and is read the same way. Cells are as printed ("-": not in the paper).

# Scandolo, Bauszat, Eisemann 2016, Merged Multiresolution Hierarchies, at 4K² 16K² 64K² 256K².
MMH_RESOLUTIONS = [4 * K, 16 * K, 64 * K, 256 * K]
# Table 1, size in MB: DAG [KSA13], MH [SBE16], MMH ("Ours", local search distance 1000).
MMH_TABLE1 = {
    "CLOSED CITY": {"DAG": "0.62 3.40 14.90 60.46", "MH": "0.41 2.10 9.33 38.43",
                    "MMH": "0.30 1.43 5.80 23.73"},
    "CITYSCAPE": {"DAG": "0.94 3.94 16.38 63.34", "MH": "0.60 2.73 11.53 47.07",
                  "MMH": "0.40 1.67 6.83 27.71"},
    "VILLA": {"DAG": "1.78 9.27 39.70 166.47", "MH": "0.88 5.01 23.61 101.52",
              "MMH": "0.63 3.62 17.36 74.11"},
    "SHIP": {"DAG": "2.01 8.66 35.57 153.67", "MH": "1.11 5.64 24.57 102.36",
             "MMH": "0.82 3.83 16.34 67.64"},
}
# Table 2, creation time in seconds: DAG [KSA15], MH, MMH.
MMH_TABLE2 = {
    "CLOSED CITY": {"DAG": "0.098 0.53 4.88 65.23", "MH": "0.27 1.24 5.80 56.17",
                    "MMH": "0.37 1.59 8.72 72.54"},
    "SHIP": {"DAG": "0.12 0.67 6.16 78.74", "MH": "0.31 1.59 7.08 69.30",
             "MMH": "0.54 3.1 15.6 109.9"},
}
# Table 3, early rejections as % of the node pairs tested: interval mismatch, offset too large,
# full test rejection (tested in that order).
MMH_TABLE3 = {
    "CLOSED CITY": {16 * K: "67.2 0.00 32.63", 64 * K: "64.8 0.28 34.76",
                    256 * K: "63.5 11.9 24.39"},
    "CITYSCAPE": {16 * K: "64.88 0.00 34.90", 64 * K: "62.15 1.49 36.21",
                  256 * K: "61.94 13.51 24.44"},
}
# Fig. 8 is a plot (size against merging time, CLOSED CITY and VILLA at 64K²) without printed
# numbers; the text calls 500–1000 a reasonable trade-off and uses 1000 throughout.
MMH_SEARCH_DISTANCES = [0, 10, 100, 250, 500, 1000, 2000, 5000, 10000]

# Scandolo, Eisemann 2021, DAG Encoding for Compressed Shadow Maps.
DAGMH_RESOLUTIONS = [4 * K << i for i in range(8)]  # 4K² … 512K²
# Table 1, size in MB: DAG [KSA15], MMH [SBE16b], DAG-MH.
DAGMH_TABLE1 = {
    "Citadel": {"DAG": "0.737 1.79 3.88 8.25 17.00 34.4 69.6 139.7",
                "MMH": "0.351 0.765 1.58 3.24 6.52 13.26 26.93 54.49",
                "DAG-MH": "0.252 0.571 1.21 2.43 4.68 8.84 16.59 31.16"},
    "City": {"DAG": "0.929 2.01 3.90 8.10 16.73 33.72 67.89 135.9",
             "MMH": "0.411 0.845 1.71 3.44 6.99 13.90 27.90 55.54",
             "DAG-MH": "0.329 0.663 1.29 2.47 4.70 8.83 16.73 31.45"},
    "Trees": {"DAG": "2.06 5.03 10.71 22.41 45.62 93.46 190.6 384.6",
              "MMH": "0.767 1.898 4.394 9.73 20.85 43.36 88.34 177.6",
              "DAG-MH": "0.480 1.23 2.96 6.54 13.66 27.53 54.19 104.9"},
    "Dinos": {"DAG": "1.82 3.67 7.29 15.21 31.93 67.24 139.1 281.4",
              "MMH": "0.875 1.79 3.69 7.65 15.90 32.41 65.41 131.2",
              "DAG-MH": "0.542 1.07 2.09 4.04 7.71 14.57 27.40 51.50"},
    "Hairball": {"DAG": "21.21 40.69 71.52 133.60 262.50 532.23 1086.56 -",
                 "MMH": "5.56 12.37 27.28 58.53 122.46 251.10 - -",
                 "DAG-MH": "3.73 8.66 18.01 35.33 67.32 127.09 239.9 -"},
}
DAGMH_UNCOMPRESSED = "64 256 1024 4096 16384 65536 262144 1048576"
# Table 2, compression time in seconds (Citadel) at 4K² 16K² 64K² 256K².
DAGMH_TABLE2_RESOLUTIONS = MMH_RESOLUTIONS
DAGMH_TABLE2 = {"DAG": "0.047 0.351 4.110 59.85", "MH": "0.251 0.774 5.488 59.30",
                "MMH": "0.257 1.465 10.67 84.42", "DAG-MH": "0.247 0.875 6.225 62.33"}
# §4.1: the dual shadow map is about 80% of DAG-MH's total creation time.
DAGMH_DEPTH_SHARE = 80
# Table 3 (Citadel), by treelet height 2 3 4 5: sizes in MB, counts.
DAGMH_TREELET_HEIGHTS = [2, 3, 4, 5]
DAGMH_TABLE3 = {
    16 * K: {"DAG structure size": "0.756 0.696 0.622 0.788",
             "Inner nodes": "52746 47086 26425 12452", "Nodes size": "0.756 0.668 0.375 0.172",
             "Treelets": "23 5683 21595 14666", "Treelets size": "<0.001 0.027 0.247 0.615"},
    64 * K: {"DAG structure size": "2.475 2.399 2.261 3.493",
             "Inner nodes": "177882 170726 124947 66475", "Nodes size": "2.475 1.585 0.831 0.704",
             "Treelets": "23 7179 47157 61164", "Treelets size": "<0.001 0.814 1.430 2.789"},
}
# Table 4 (Citadel), by values per chunk 16 32 64 128. The 64K² "chunks factors size" at 16 is
# printed 0.169, but the row's own sum (2.897 − 1.728) says 1.169.
DAGMH_CHUNK_SIZES = [16, 32, 64, 128]
DAGMH_TABLE4 = {
    16 * K: {"DAG values size": "0.688 0.588 0.578 0.592",
             "Chunks map size": "0.397 0.220 0.132 0.088",
             "Chunks factors size": "0.291 0.368 0.446 0.504",
             "Avg. factor qty": "57.6% 61.5% 64.6% 67.7%",
             "Avg. factor bits": "10.95 13.09 15.33 16.71"},
    64 * K: {"DAG values size": "2.897 2.423 2.362 2.388",
             "Chunks map size": "1.728 0.960 0.576 0.384",
             "Chunks factors size": "0.169 1.463 1.786 2.004",
             "Avg. factor qty": "52.6% 56.3% 59.5% 62.3%",
             "Avg. factor bits": "10.87 12.89 15.13 16.48"},
}
# Lookup cost, as the papers state it in words (GPU, a full HD view, hierarchical PCF):
# MMH 2016 §4: at 256K² below 1 ms per frame for single queries, 1–2.5 ms with 3×3 PCF, and no
# measurable difference to MH. DAG-MH 2021 §4.2 (Citadel, 64K²): about 0.5 ms single, 1 ms 3×3,
# 2.5 ms 5×5; single queries about as fast as MMH, 3×3 and 5×5 about half as fast.
DAGMH_LOOKUP_MS = {1: 0.5, 3: 1.0, 5: 2.5}
