// Included: its variables become the includer's.
block = [3, 2, 1];
