#!/usr/bin/env python3
# Q4 (2x2 Gauss) plane stress on Cook's membrane, structured n x n, dense Gauss elimination (small n).
import sys
def solve(K, F):
    n=len(F); A=[row[:] + [F[i]] for i,row in enumerate(K)]
    for k in range(n):
        p=max(range(k,n),key=lambda r:abs(A[r][k])); A[k],A[p]=A[p],A[k]
        for r in range(k+1,n):
            m=A[r][k]/A[k][k]
            if m:
                for c in range(k,n+1): A[r][c]-=m*A[k][c]
    x=[0]*n
    for k in range(n-1,-1,-1): x[k]=(A[k][n]-sum(A[k][c]*x[c] for c in range(k+1,n)))/A[k][k]
    return x
def cook(n,E=1.0,nu=1/3.0):
    X=[]
    for j in range(n+1):
        for i in range(n+1):
            s=i/n;t=j/n;yb=44*s;yt=44+16*s;X.append((48*s,yb+t*(yt-yb)))
    N=len(X); idx=lambda i,j:j*(n+1)+i
    f=E/(1-nu*nu); D=[[f,f*nu,0],[f*nu,f,0],[0,0,f*(1-nu)/2]]
    K=[[0.0]*(2*N) for _ in range(2*N)]
    g=3**-0.5
    for j in range(n):
        for i in range(n):
            nodes=[idx(i,j),idx(i+1,j),idx(i+1,j+1),idx(i,j+1)]
            xy=[X[k] for k in nodes]
            ke=[[0.0]*8 for _ in range(8)]
            for xi in (-g,g):
                for eta in (-g,g):
                    dN=[[-(1-eta)/4,-(1-xi)/4],[(1-eta)/4,-(1+xi)/4],[(1+eta)/4,(1+xi)/4],[-(1+eta)/4,(1-xi)/4]]
                    J=[[sum(dN[a][0]*xy[a][0] for a in range(4)),sum(dN[a][0]*xy[a][1] for a in range(4))],
                       [sum(dN[a][1]*xy[a][0] for a in range(4)),sum(dN[a][1]*xy[a][1] for a in range(4))]]
                    det=J[0][0]*J[1][1]-J[0][1]*J[1][0]
                    Ji=[[J[1][1]/det,-J[0][1]/det],[-J[1][0]/det,J[0][0]/det]]
                    B=[[0.0]*8 for _ in range(3)]
                    for a in range(4):
                        dx=Ji[0][0]*dN[a][0]+Ji[0][1]*dN[a][1]; dy=Ji[1][0]*dN[a][0]+Ji[1][1]*dN[a][1]
                        B[0][2*a]=dx;B[1][2*a+1]=dy;B[2][2*a]=dy;B[2][2*a+1]=dx
                    for r in range(8):
                        for c in range(8):
                            ke[r][c]+=det*sum(B[p][r]*sum(D[p][q]*B[q][c] for q in range(3)) for p in range(3))
            dofs=sum(([2*k,2*k+1] for k in nodes),[])
            for r in range(8):
                for c in range(8): K[dofs[r]][dofs[c]]+=ke[r][c]
    F=[0.0]*(2*N)
    for j in range(n):
        a,b=idx(n,j),idx(n,j+1);L=X[b][1]-X[a][1];F[2*a+1]+=0.5*L/16;F[2*b+1]+=0.5*L/16
    free=[k for k in range(2*N) if not (k//2)%(n+1)==0]
    Kf=[[K[r][c] for c in free] for r in free]; Ff=[F[r] for r in free]
    u=solve(Kf,Ff); full=dict(zip(free,u))
    return full[2*idx(n,n)+1]
for n in map(int,sys.argv[1:]): print(n,cook(n))
