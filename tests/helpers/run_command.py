"""What the tests of ``dptbd run`` (``tests/commands/run/``) share: a small scenario file's
text, and what a run left in a folder."""

SMALL = """\
name = "small"
[scene]
size = [32, 32]
frames = 24
snr = 5.0
seed = 3
[[scene.targets]]
start = [6.0, 6.0]
velocity = [0.8, 0.6]
[segmentation]
false_alarm_rate = 0.005
"""


def leftovers(folder):
    """Everything in ``folder`` except the inputs folder (partial or output folders)."""
    return sorted(p.name for p in folder.iterdir() if p.name != "inputs")
