within Lib.Sub;
model Holder "Holds a Faulty one level down"
  Faulty f;
end Holder;
