"""vlab: a virtual material-testing lab.

Data flow: scene (TOML) -> geometry (mesh with named regions) -> fe (Newton on the total
energy) -> measure (load cell, extensometers, E and nu) -> report (CSV, JSON, PNG, HTML).
"""

__version__ = "0.1.0"
