within Lib;
model Resistor
  parameter Real R = two "resistance, from the enclosing package";
  Real v = sin(time);
  Real i;
equation
  v = R * i;
end Resistor;
