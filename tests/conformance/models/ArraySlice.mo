// name:     ArraySlice
// keywords: array slicing
// status:   correct
//
// Drmodelica: 7.7 Built-in Functions (p. 225)
// cflags: -d=-newInst
//

model ArraySlice
    Real T[30](start=ones(30)*200);
    Real Tin=100;
    Real temp[30](start=zeros(30));
equation
    temp[1]=100.0;
    temp[2:30]=T[2:30];
    der(T)=temp;
end ArraySlice;

// (the published file continues with OpenModelica's flattened model, 150
// comment lines, omitted here)
