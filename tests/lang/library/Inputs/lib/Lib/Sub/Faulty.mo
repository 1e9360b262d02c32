within Lib.Sub;
model Faulty "A library model with an error in it"
  parameter Real k = gian;
  Real x;
equation
  x = k;
end Faulty;
