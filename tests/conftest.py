import os
import sys
from pathlib import Path

from hypothesis import settings

# the tests share small helpers (corpus locations, program builders)
sys.path.insert(0, str(Path(__file__).parent))

# CI: derandomised, bounded and without deadlines on a small noisy machine
settings.register_profile("ci", deadline=None, derandomize=True, max_examples=100, print_blob=True)
settings.register_profile("dev", deadline=None, max_examples=100)
settings.load_profile("ci" if os.environ.get("CI") else os.environ.get("HYPOTHESIS_PROFILE", "dev"))
