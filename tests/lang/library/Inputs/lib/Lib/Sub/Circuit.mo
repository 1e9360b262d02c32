within Lib.Sub;
model Circuit
  Resistor r(R = 4);
  Broken.Missing m if false;
end Circuit;
