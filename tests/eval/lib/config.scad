// Included: its variables become the includer's.
size = 3;
label = "config";
