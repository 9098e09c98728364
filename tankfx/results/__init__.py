"""From a solved model to what a user reads: the results.json contract, the structure's
results, the overturning's superposition, the fields and profiles written to files, the
summary and report, and the figures. Nothing below this layer imports the figures."""
