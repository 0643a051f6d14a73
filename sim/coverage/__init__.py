"""Coverage of the verification campaign: functional bins (:mod:`.bins`) and code coverage."""
