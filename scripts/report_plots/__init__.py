"""Figure modules of scripts/plot_report.py: each exposes draw(directory, out_dir, dpi) and
returns the names of the PNG files it wrote (none when the directory holds nothing for it)."""
