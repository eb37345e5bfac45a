"""The env presets (YAML), installed as ``bbgym/configs``: ``bbgym.config`` loads them."""
